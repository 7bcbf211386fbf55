#include "engine/task/task_conflict_detection.h"

#include <algorithm>
#include <unordered_map>
#include <vector>

#include "engine/collision/collision_queries.h"
#include "engine/core/value_hash.h"
#include "engine/placement/placement_region.h"
#include "engine/task/move_out_sampler.h"

namespace dash {

namespace {
constexpr double kMinLocationSpacing = 0.085;  // centre distance kept between a resampled pose and others
constexpr int kResampleAttempts = 200;

bool isObjectMove(TaskArcType t) {
  return t == TaskArcType::kPick || t == TaskArcType::kPlace || t == TaskArcType::kHandover;
}
}  // namespace

struct TaskConflictDetector::Trace {
  std::vector<ObjectLayout> before;            ///< objects resting just before each step
  std::vector<std::vector<int>> location;      ///< each object's location before each step (-1: held)
  ObjectLayout empty;
};

// Depth-first search for one object's transition configurations along its steps. The grasp chosen when
// a robot takes the object (pick or handover) fixes X_TO until it lets go, so the steps of one object
// are solved together, backtracking over grasp candidates and handover poses within a budget.
class ChainSearch {
 public:
  ChainSearch(TransitionSampler& sampler, const TaskSpace& space, const TaskPlan& plan,
              const std::vector<ObjectLayout>& before, const ObjectLayout& empty, std::vector<int> steps, int object,
              bool use_objects, const TaskConflictParams& params, const RejectedConfigurations& rejected,
              const Deadline& deadline)
      : deadline_(deadline),
        sampler_(sampler), space_(space), plan_(plan), before_(before), empty_(empty), steps_(std::move(steps)),
        object_(object), use_objects_(use_objects), params_(params), rejected_(rejected),
        assignment_(steps_.size()) {}

  bool run() { return solved_ = solve(0, Pose::Identity()); }
  bool solved() const { return solved_; }
  const std::vector<TransitionConfig>& assignment() const { return assignment_; }
  const std::vector<int>& steps() const { return steps_; }
  /// The position in steps() the search got stuck at most deeply.
  std::size_t deepest() const { return deepest_; }
  /// The search ran out of its budget (so its failure proves nothing).
  bool exhausted() const { return budget_ < 0; }

 private:
  const ObjectLayout& layoutAt(int step) const { return use_objects_ ? before_[step] : empty_; }

  bool free(const RobotState& state, int step) {
    if (rejected_.contains(state.robot, state.q)) return false;  // the motion layer could not reach it
    if (!use_objects_) return true;
    return !robotInCollision(sampler_.world(), sampler_.context(), state, before_[step], nullptr,
                             CheckScope::kObjectsOnly);
  }

  /// Look-ahead: when the chain's next step places the object with the grasp X_TO taken at step i,
  /// some configuration must hold it there (statically); otherwise every choice after this one fails
  /// at that place and the search would spend its budget proving it (a side grasp taken in a
  /// handover that does not fit into a shelf cubby).
  bool placeableNext(std::size_t i, const Pose& X_TO) {
    if (i + 1 >= steps_.size()) return true;
    const TaskArc& next = plan_.steps[steps_[i + 1]].action;
    if (next.type != TaskArcType::kPlace) return true;
    if (!sampler_.holdConfigs(next.robot, object_, space_.location(object_, next.location).X_WO, X_TO, 1).empty())
      return true;
    deepest_ = std::max(deepest_, i + 1);  // it is the place that fails with this grasp
    return false;
  }

  /// Whether a handover's giver and receiver collide at step k, remembered within this search: the
  /// depth-first search meets the same pair again whenever earlier choices lead to the same grasp (each
  /// grasp comes with several configurations), and the answer depends on nothing else (the step's
  /// layout is fixed). The budget counts search nodes, not checks, so the search is the same.
  bool handoverCollides(const RobotState (&states)[2], int k) {
    std::vector<double>& key = key_;  // reused: most calls find their key
    key.assign(1, static_cast<double>(k));
    for (const RobotState& s : states) {
      key.push_back(s.robot);
      key.insert(key.end(), s.q.data(), s.q.data() + s.q.size());
      key.push_back(s.held.object);
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 3; ++r) key.push_back(s.held.X_TO.matrix()(r, c));
    }
    if (const auto it = handover_verdicts_.find(key); it != handover_verdicts_.end()) return it->second;
    const bool collides = robotsInCollision(sampler_.world(), sampler_.context(), states, layoutAt(k), nullptr,
                                            use_objects_ ? CheckScope::kAll : CheckScope::kStaticOnly);
    handover_verdicts_.emplace(key, collides);
    return collides;
  }

  bool solve(std::size_t i, const Pose& X_TO) {
    if (i == steps_.size()) return true;
    deepest_ = std::max(deepest_, i);
    if (--budget_ < 0 || deadline_.expired()) {
      budget_ = -1;
      return false;
    }
    const int k = steps_[i];
    const TaskArc& a = plan_.steps[k].action;
    const int o = object_;
    switch (a.type) {
      case TaskArcType::kPick: {
        const Pose X_WO = space_.location(o, a.location).X_WO;
        for (const GraspConfig& gc : sampler_.graspConfigs(a.robot, o, X_WO, a.grasp, params_.grasp_candidates, params_.prefer_free_approach)) {
          if (!free({a.robot, gc.q, HeldObject{o, gc.X_TO}}, k)) continue;
          if (!placeableNext(i, gc.X_TO)) continue;
          assignment_[i] = {true, gc.q, {}, X_WO, gc.X_TO, Pose::Identity()};
          if (solve(i + 1, gc.X_TO)) return true;
          if (budget_ < 0) return false;
        }
        return false;
      }
      case TaskArcType::kPlace: {
        const Pose X_WO = space_.location(o, a.location).X_WO;
        for (const JointVector& q : sampler_.holdConfigs(a.robot, o, X_WO, X_TO, 3, params_.prefer_free_approach)) {
          if (!free({a.robot, q, HeldObject{o, X_TO}}, k)) continue;
          assignment_[i] = {true, q, {}, X_WO, X_TO, Pose::Identity()};
          return solve(i + 1, Pose::Identity());  // the next step starts a new grasp: no reason to retry
        }
        return false;
      }
      case TaskArcType::kHandover: {
        const std::vector<Pose> poses = sampler_.handoverPoses(a.robot, a.robot2);
        const int tries = std::min<int>(params_.handover_poses, static_cast<int>(poses.size()));
        for (int p = 0; p < tries; ++p) {
          const Pose& X_WO = poses[p];
          const std::vector<JointVector> givers = sampler_.holdConfigs(a.robot, o, X_WO, X_TO, 2);
          if (givers.empty()) continue;
          const std::vector<GraspConfig> receivers = sampler_.graspConfigs(a.robot2, o, X_WO, a.grasp2, 4);
          for (const JointVector& q1 : givers)
            for (const GraspConfig& gc2 : receivers) {
              if (rejected_.contains(a.robot, q1) || rejected_.contains(a.robot2, gc2.q)) continue;
              const RobotState states[2] = {{a.robot, q1, HeldObject{o, X_TO}}, {a.robot2, gc2.q, HeldObject{}}};
              if (handoverCollides(states, k)) continue;
              if (!placeableNext(i, gc2.X_TO)) continue;
              assignment_[i] = {true, q1, gc2.q, X_WO, X_TO, gc2.X_TO};
              if (solve(i + 1, gc2.X_TO)) return true;
              if (budget_ < 0) return false;
            }
        }
        return false;
      }
      default:
        return solve(i + 1, X_TO);
    }
  }

  const Deadline& deadline_;
  TransitionSampler& sampler_;
  const TaskSpace& space_;
  const TaskPlan& plan_;
  const std::vector<ObjectLayout>& before_;
  const ObjectLayout& empty_;
  std::vector<int> steps_;
  int object_;
  bool use_objects_;
  const TaskConflictParams& params_;
  const RejectedConfigurations& rejected_;
  std::vector<TransitionConfig> assignment_;
  std::size_t deepest_ = 0;
  int budget_ = params_.chain_budget;
  bool solved_ = false;
  std::unordered_map<std::vector<double>, bool, DoublesHash> handover_verdicts_;
  std::vector<double> key_;
};

TaskConflictDetector::TaskConflictDetector(TransitionSampler& sampler, TaskSpace& space, const TaskHypergraph& graph,
                                           Rng& rng, TaskConflictParams params)
    : sampler_(&sampler), space_(&space), graph_(&graph), rng_(&rng), params_(params) {}

void TaskConflictDetector::traceLayouts(const TaskPlan& plan, Trace& trace) const {
  const Scene& scene = space_->scene();
  ObjectLayout layout = ObjectLayout::atStart(scene);
  std::vector<int> location(scene.objects.size());
  for (int o = 0; o < space_->objectCount(); ++o) {
    location[o] = space_->startLocation(o);
    layout.place(o, space_->location(o, location[o]).X_WO);
  }
  trace.empty = ObjectLayout::empty(scene);
  trace.before.reserve(plan.steps.size());
  for (const TaskStep& step : plan.steps) {
    trace.before.push_back(layout);
    trace.location.push_back(location);
    const TaskArc& a = step.action;
    if (a.type == TaskArcType::kPick) {
      layout.remove(a.object);
      location[a.object] = -1;
    } else if (a.type == TaskArcType::kPlace) {
      layout.place(a.object, space_->location(a.object, a.location).X_WO);
      location[a.object] = a.location;
    }
  }
}

VertexId TaskConflictDetector::producedElement(const TaskStep& step) const {
  const TaskArc& a = step.action;
  const TaskGraph& g = graph_->graph();
  for (VertexId v : g.head(step.arc)) {
    const TaskElement& e = g.property(v);
    if (a.type == TaskArcType::kPlace && e.kind == ElementKind::kObjectAt) return v;
    if (a.type == TaskArcType::kPick && e.kind == ElementKind::kHolding) return v;
    if (a.type == TaskArcType::kHandover && e.kind == ElementKind::kHolding) return v;
    if (a.type == TaskArcType::kInspect && e.kind == ElementKind::kTaskDone) return v;
  }
  return {};
}

bool TaskConflictDetector::resampleLocation(int object, int location, const Trace&) {
  const Scene& scene = space_->scene();
  const ObjectLocation& loc = space_->location(object, location);
  if (!loc.resampleable || loc.surface < 0) return false;
  const PlacementRegion region(scene.surfaces[loc.surface]);
  const BoxShape& box = scene.objects[object].shape;
  ObjectLayout none = ObjectLayout::empty(scene);
  for (int attempt = 0; attempt < kResampleAttempts; ++attempt) {
    const auto pose = region.sample(box, *rng_, 16);
    if (!pose) continue;
    bool clear = true;
    for (int o = 0; o < space_->objectCount() && clear; ++o)
      for (int l = 0; l < static_cast<int>(space_->locations(o).size()) && clear; ++l) {
        if (o == object && l == location) continue;
        const Vec3 d = space_->location(o, l).X_WO.translation() - pose->translation();
        clear = d.norm() >= kMinLocationSpacing;
      }
    if (!clear || objectInCollision(sampler_->world(), sampler_->context(), object, *pose, none)) continue;
    space_->resample(object, location, *pose);
    return true;
  }
  return false;
}

// Vertex-vertex conflicts between object poses: a placement onto a spot another object occupies.
bool TaskConflictDetector::resolvePoseConflicts(const TaskPlan& plan, const Trace& trace, TaskConflictResult& result) {
  const Scene& scene = space_->scene();
  bool resampled = false;
  for (std::size_t k = 0; k < plan.steps.size(); ++k) {
    const TaskArc& a = plan.steps[k].action;
    if (a.type != TaskArcType::kPlace) continue;
    CollisionReport report;
    if (!objectInCollision(sampler_->world(), sampler_->context(), a.object, space_->location(a.object, a.location).X_WO,
                           trace.before[k], &report))
      continue;
    const int other = report.b.kind == CollisionElement::Kind::kObject ? report.b.index : -1;
    const std::string what = "pose conflict: " + space_->locationLabel(a.object, a.location) + " (" +
                             describe(report, scene) + ") at step " + std::to_string(k);
    if (resampleLocation(a.object, a.location, trace)) {
      result.conflicts.push_back(what + ": resampled " + space_->locationLabel(a.object, a.location));
      ++result.resampled;
      resampled = true;
    } else if (other >= 0 && trace.location[k][other] >= 0 && resampleLocation(other, trace.location[k][other], trace)) {
      result.conflicts.push_back(what + ": resampled " + space_->locationLabel(other, trace.location[k][other]));
      ++result.resampled;
      resampled = true;
    } else if (other >= 0) {
      addBlockerConstraints(plan, trace, static_cast<int>(k), {other}, result);
      result.conflicts.push_back(what);
    }
    if (resampled) return true;  // layouts changed: the next pass traces them again
  }
  return false;
}

void TaskConflictDetector::addBlockerConstraints(const TaskPlan& plan, const Trace& trace, int step,
                                                 const std::vector<int>& blockers, TaskConflictResult& result) {
  const VertexId post = producedElement(plan.steps[step]);
  if (!post.valid()) return;
  for (int b : blockers) {
    const int lb = trace.location[step][b];
    if (lb < 0) continue;
    const auto pre = graph_->find(TaskElement::objectAt(b, lb));
    if (!pre) continue;
    const ObjectLocation& where = space_->location(b, lb);
    TaskConstraint c;
    // A blocker at its final goal will not move again: once it is there, the blocked transition can
    // never happen (history constraint). Anywhere else it may move away (frontier constraint).
    const bool final_goal = where.kind == ObjectLocation::Kind::kGoal && space_->extraLocationCount(b) == 0;
    c.kind = final_goal ? TaskConstraint::Kind::kHistory : TaskConstraint::Kind::kFrontier;
    c.pre = *pre;
    c.post = post;
    const TaskElement& produced = graph_->graph().property(post);
    c.post_required =
        produced.kind == ElementKind::kObjectAt && produced.location == space_->goalLocation(produced.object);
    c.cause = "step " + std::to_string(step) + " (" + describeStep(plan.steps[step], *space_) + ") blocked by " +
              space_->locationLabel(b, lb);
    result.constraints.push_back(c);
    // The blocker must leave a place it has to end at, and has nowhere else to go: expand.
    const bool anchored = where.isStart() && (where.isGoal() || space_->goalLocation(b) < 0);
    if (anchored && !space_->isFixed(b) && space_->extraLocationCount(b) == 0 &&
        std::find(result.expand_objects.begin(), result.expand_objects.end(), b) == result.expand_objects.end())
      result.expand_objects.push_back(b);
  }
}

bool TaskConflictDetector::handoverPossible(int giver, int receiver, int object, GraspClass g1, GraspClass g2) {
  const Vec3& size = space_->scene().objects[object].shape.size;
  const auto key = std::make_tuple(giver, receiver, static_cast<int>(g1), static_cast<int>(g2),
                                   std::lround(size.x() * 1e4), std::lround(size.y() * 1e4), std::lround(size.z() * 1e4));
  if (auto it = handover_possible_.find(key); it != handover_possible_.end()) return it->second;
  const ObjectLayout none = ObjectLayout::empty(space_->scene());
  bool possible = false;
  for (const Pose& X_WO : sampler_->handoverPoses(giver, receiver)) {
    const std::vector<GraspConfig> givers = sampler_->graspConfigs(giver, object, X_WO, g1, 4);
    if (givers.empty()) continue;
    for (const GraspConfig& gc2 : sampler_->graspConfigs(receiver, object, X_WO, g2, 4)) {
      for (const GraspConfig& gc1 : givers) {
        const RobotState states[2] = {{giver, gc1.q, HeldObject{object, gc1.X_TO}}, {receiver, gc2.q, HeldObject{}}};
        if (!robotsInCollision(sampler_->world(), sampler_->context(), states, none, nullptr, CheckScope::kStaticOnly)) {
          possible = true;
          break;
        }
      }
      if (possible) break;
    }
    if (possible) break;
  }
  handover_possible_.emplace(key, possible);
  return possible;
}

bool TaskConflictDetector::banImpossibleHandovers(const TaskPlan& plan, const std::vector<int>& chain, int o,
                                                  TaskConflictResult& result) {
  // A handover that is impossible whatever the grasps (an arm on each side of a wall) is an
  // interaction constraint at once; searching the chain around it would try every pose on every branch.
  bool impossible = false;
  for (int k : chain) {
    const TaskArc& a = plan.steps[k].action;
    if (a.type != TaskArcType::kHandover || handoverPossible(a.robot, a.robot2, o, a.grasp, a.grasp2)) continue;
    TaskConstraint c;
    c.kind = TaskConstraint::Kind::kInteraction;
    c.giver = a.robot;
    c.receiver = a.robot2;
    c.giver_grasp = a.grasp;
    c.receiver_grasp = a.grasp2;
    c.cause = "step " + std::to_string(k) + " (" + describeStep(plan.steps[k], *space_) +
              "): no collision-free handover configuration at any sampled pose";
    result.constraints.push_back(c);
    result.conflicts.push_back(c.cause);
    impossible = true;
  }
  return impossible;
}

void TaskConflictDetector::banUnservedStep(const TaskPlan& plan, int k, bool past_first_or_budget,
                                           TaskConflictResult& result) {
  const TaskStep& step = plan.steps[k];
  TaskConstraint c;
  c.kind = TaskConstraint::Kind::kInteraction;
  if (past_first_or_budget) {
    // The search got past the chain's first transitions: no grasp serves them and this one together
    // (a pick from one pose and a place at another with the same grasp), though each may be
    // feasible alone; or it ran out of budget. Banning this hyperarc for ever could remove the
    // object's only way to its goal; it is banned for some task queries, as a motion failure is
    // (TaskLayer::addConstraint).
    c.arc = step.arc;
    c.temporary = true;
  } else if (step.action.type == TaskArcType::kHandover) {
    c.giver = step.action.robot;
    c.receiver = step.action.robot2;
    c.giver_grasp = step.action.grasp;
    c.receiver_grasp = step.action.grasp2;
  } else {
    c.arc = step.arc;
  }
  c.cause = "step " + std::to_string(k) + " (" + describeStep(step, *space_) +
            "): no collision-free transition configuration";
  result.constraints.push_back(c);
  result.conflicts.push_back(c.cause);
}

void TaskConflictDetector::solveObjectChains(const TaskPlan& plan, const Trace& trace, const Deadline& deadline,
                                             TaskConflictResult& result) {
  std::vector<std::vector<int>> chains(static_cast<std::size_t>(space_->objectCount()));
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k)
    if (isObjectMove(plan.steps[k].action.type)) chains[plan.steps[k].action.object].push_back(k);
  for (int o = 0; o < space_->objectCount(); ++o) {
    if (chains[o].empty()) continue;
    if (deadline.expired()) {
      result.interrupted = true;
      return;
    }
    if (banImpossibleHandovers(plan, chains[o], o, result)) continue;
    // Configurations the motion layer could not reach are avoided while the chain has others; with no
    // others, they are used again (the motion layer then bans the hyperarc instead).
    auto search = [&](bool use_objects) {
      ChainSearch avoiding(*sampler_, *space_, plan, trace.before, trace.empty, chains[o], o, use_objects, params_,
                           *rejected_, deadline);
      if (avoiding.run() || rejected_->size() == 0 || deadline.expired()) return avoiding;
      ChainSearch any(*sampler_, *space_, plan, trace.before, trace.empty, chains[o], o, use_objects, params_,
                      kNoneRejected, deadline);
      any.run();
      return any;
    };
    const ChainSearch full = search(true);
    if (full.solved()) {
      for (std::size_t i = 0; i < chains[o].size(); ++i) result.transitions[chains[o][i]] = full.assignment()[i];
      continue;
    }
    if (deadline.expired()) {
      result.interrupted = true;
      return;
    }
    const ChainSearch alone = search(false);
    if (deadline.expired()) {
      result.interrupted = true;
      return;
    }
    if (alone.solved()) {
      // Feasible without the resting objects: they are what blocks it. Name every blocker.
      bool any = false;
      for (std::size_t i = 0; i < chains[o].size(); ++i) {
        const int k = chains[o][i];
        const TransitionConfig& tc = alone.assignment()[i];
        const TaskArc& a = plan.steps[k].action;
        const bool received = a.type == TaskArcType::kHandover;
        std::vector<int> blockers =
            sampler_->blockingObjects({a.robot, tc.q, HeldObject{o, tc.X_TO}}, trace.before[k]);
        if (received) {
          const auto more = sampler_->blockingObjects({a.robot2, tc.q2, HeldObject{o, tc.X_TO2}}, trace.before[k]);
          blockers.insert(blockers.end(), more.begin(), more.end());
        }
        if (blockers.empty()) continue;
        any = true;
        addBlockerConstraints(plan, trace, k, blockers, result);
        result.conflicts.push_back("step " + std::to_string(k) + " (" + describeStep(plan.steps[k], *space_) +
                                   "): transition configuration blocked by " + std::to_string(blockers.size()) +
                                   " resting object(s)");
      }
      if (!any)  // only the search budget stood in the way; the object-free solution is valid
        for (std::size_t i = 0; i < chains[o].size(); ++i) result.transitions[chains[o][i]] = alone.assignment()[i];
      continue;
    }
    // No collision-free transition configuration even without resting objects.
    const std::size_t at = std::min(alone.deepest(), chains[o].size() - 1);
    const int k = chains[o][at];
    if (resampleChainLocation(plan, trace, chains[o], at, result)) continue;
    banUnservedStep(plan, k, at > 0 || alone.exhausted(), result);
  }
}

bool TaskConflictDetector::resampleChainLocation(const TaskPlan& plan, const Trace& trace,
                                                 const std::vector<int>& chain, std::size_t at,
                                                 TaskConflictResult& result) {
  const int step = chain[at];
  // The failing step's own move-out pose, or else the last one the chain passes before it (a place at
  // the goal that no grasp taken at that move-out fits).
  const TaskArc* moved_out = nullptr;
  for (std::size_t i = at + 1; i-- > 0 && !moved_out;) {
    const TaskArc& b = plan.steps[chain[i]].action;
    if ((b.type == TaskArcType::kPlace || b.type == TaskArcType::kPick) && b.location >= 0 &&
        space_->location(b.object, b.location).resampleable)
      moved_out = &b;
  }
  if (!moved_out) return false;
  const TaskArc& a = *moved_out;
  int& done = chain_resamples_[{a.object, a.location}];
  if (done >= params_.chain_location_resamples) return false;
  const std::optional<MoveOutPose> moved = move_outs_ ? move_outs_->forResample(a.object, *rng_) : std::nullopt;
  if (moved)
    space_->resample(a.object, a.location, moved->X_WO, moved->surface);
  else if (!resampleLocation(a.object, a.location, trace))
    return false;
  ++done;
  ++result.resampled;
  ++result.move_outs_resampled;
  result.conflicts.push_back("step " + std::to_string(step) + " (" + describeStep(plan.steps[step], *space_) +
                             "): no collision-free transition configuration: resampled " +
                             space_->locationLabel(a.object, a.location));
  return true;
}

void TaskConflictDetector::solveInspections(const TaskPlan& plan, const Trace& trace, TaskConflictResult& result) {
  const Scene& scene = space_->scene();
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    const TaskStep& step = plan.steps[k];
    if (step.action.type != TaskArcType::kInspect) continue;
    const Pose& X_WT = scene.tasks[step.action.task].X_WT;
    std::vector<int> best_blockers;
    bool found = false, statically = false;
    for (const JointVector& q : sampler_->ikSolutions(step.action.robot, X_WT)) {
      const RobotState state{step.action.robot, q, HeldObject{}};
      if (!sampler_->staticFree(state)) continue;
      statically = true;
      std::vector<int> blockers = sampler_->blockingObjects(state, trace.before[k]);
      if (blockers.empty()) {
        result.transitions[k] = {true, q, {}, X_WT, Pose::Identity(), Pose::Identity()};
        found = true;
        break;
      }
      if (best_blockers.empty() || blockers.size() < best_blockers.size()) best_blockers = blockers;
    }
    if (found) continue;
    if (statically) {
      addBlockerConstraints(plan, trace, k, best_blockers, result);
      result.conflicts.push_back("step " + std::to_string(k) + " (inspection) blocked by resting objects");
    } else {
      TaskConstraint c;
      c.kind = TaskConstraint::Kind::kInteraction;
      c.arc = step.arc;
      c.cause = "step " + std::to_string(k) + ": inspection pose unreachable without collision";
      result.constraints.push_back(c);
      result.conflicts.push_back(c.cause);
    }
  }
}

TaskConflictResult TaskConflictDetector::detect(const TaskPlan& plan, const Deadline& deadline) {
  TaskConflictResult result;
  result.transitions.resize(plan.steps.size());
  const std::uint64_t checks_before = sampler_->context().counters().configuration_checks;
  Trace trace;
  traceLayouts(plan, trace);
  if (!resolvePoseConflicts(plan, trace, result)) {
    solveObjectChains(plan, trace, deadline, result);
    solveInspections(plan, trace, result);
  }
  result.configuration_checks = sampler_->context().counters().configuration_checks - checks_before;
  return result;
}

}  // namespace dash
