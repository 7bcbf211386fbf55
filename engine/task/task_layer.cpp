#include "engine/task/task_layer.h"

#include <algorithm>

#include "engine/collision/collision_queries.h"
#include "engine/placement/placement_region.h"

namespace dash {

namespace {
constexpr double kMoveOutRadius = 0.75;      // around the robot base that will move the object out
constexpr double kMoveOutSpacing = 0.09;     // centre distance to every other known object location
constexpr int kMoveOutAttempts = 400;

log::ConstraintKind toLogKind(TaskConstraint::Kind k) {
  switch (k) {
    case TaskConstraint::Kind::kFrontier: return log::ConstraintKind::Frontier;
    case TaskConstraint::Kind::kHistory: return log::ConstraintKind::History;
    case TaskConstraint::Kind::kInteraction: return log::ConstraintKind::Interaction;
  }
  return log::ConstraintKind::Frontier;
}
}  // namespace

const char* toString(TaskLayerStatus status) {
  switch (status) {
    case TaskLayerStatus::kFeasible: return "feasible";
    case TaskLayerStatus::kInfeasible: return "infeasible";
    case TaskLayerStatus::kTimeout: return "timeout";
  }
  return "?";
}

TaskLayer::TaskLayer(const Scene& scene, const CollisionWorld& world, CollisionContext& context,
                     log::EventEmitter& emitter, std::uint64_t seed, TaskLayerParams params)
    : scene_(&scene),
      emitter_(&emitter),
      params_(params),
      seed_(seed),
      rng_(Rng::derive(seed, 11)),
      space_(scene),
      sampler_(world, context),
      reachability_(sampler_, params_.reachability) {
  // A task that needs an object out of the way (a lid) needs somewhere to put it: one resampleable
  // extra location each, the minimal task space that can express the task.
  for (const SceneTask& task : scene.tasks)
    if (task.requires_removed_object >= 0 && space_.extraLocationCount(task.requires_removed_object) == 0)
      expand(task.requires_removed_object, "inspect task needs it away from its start");
}

TaskLayerSizes TaskLayer::sizes() const {
  return {graph_.graph().vertexCount(), graph_.graph().hyperarcCount(), extended_vertices_, extended_hyperarcs_};
}

void TaskLayer::rebuild() {
  log::PhaseTimer timer(*emitter_, log::Phase::TaskConstruction);
  const TaskGraph& g = graph_.graph();
  TaskHypergraph::Observer observer;
  if (emitter_->enabled()) {
    observer.onVertex = [&](VertexId v, const TaskElement& e) {
      emitter_->vertex(log::Layer::Task, v.value(), elementLabel(e, space_));
    };
    observer.onHyperarc = [&](HyperarcId a, const TaskArc& arc) {
      emitter_->hyperarcOf(log::Layer::Task, taskArcTypeName(arc.type), a.value(), g.head(a), g.tail(a));
    };
  }
  graph_.build(space_, reachability_.oracle(), observer);
}

namespace {

/// What a temporary ban is counted by: its hyperarc, or its handover class (giver, receiver, grasps).
std::uint64_t banKey(const TaskConstraint& c) {
  if (c.arc.valid()) return c.arc.value();
  return (std::uint64_t{1} << 40) | (static_cast<std::uint64_t>(c.giver) << 24) |
         (static_cast<std::uint64_t>(c.receiver) << 8) | (static_cast<std::uint64_t>(c.giver_grasp) << 4) |
         static_cast<std::uint64_t>(c.receiver_grasp);
}

}  // namespace

bool TaskLayer::addConstraint(const TaskConstraint& given) {
  TaskConstraint c = given;
  // A motion failure at a handover is one of its configurations (the handover pose sampled for that
  // pair of robots and grasps), which every object of that size shares: the whole class is banned,
  // so that the next schedule does not try the same handover with the next object.
  if (params_.handover_class_bans && c.temporary && c.from_motion && c.arc.valid() &&
      graph_.graph().property(c.arc).type == TaskArcType::kHandover) {
    const TaskArc& a = graph_.graph().property(c.arc);
    c.arc = HyperarcId();
    c.giver = a.robot;
    c.receiver = a.robot2;
    c.giver_grasp = a.grasp;
    c.receiver_grasp = a.grasp2;
  }
  if (c.temporary) c.queries = std::min(++motion_failures_[banKey(c)], params_.max_ban_queries);
  if (!constraints_.add(c)) return false;
  std::string content;
  std::vector<std::uint32_t> vertices;
  if (c.kind == TaskConstraint::Kind::kInteraction) {
    if (c.arc.valid()) {
      content = "forbid " + graph_.label(c.arc, space_);
    } else {
      content = "forbid handover " + scene_->robots[c.giver].id + " -> " + scene_->robots[c.receiver].id + " (" +
                graspClassName(c.giver_grasp) + " -> " + graspClassName(c.receiver_grasp) + ")";
    }
  } else {
    content = "(" + graph_.label(c.pre, space_) + ", " + graph_.label(c.post, space_) + ")";
    vertices = {c.pre.value(), c.post.value()};
  }
  // A motion failure whose task plan spent its motion budget comes back as a task constraint (a
  // temporary ban on the hyperarc); the motion constraints before it are logged by the planner.
  const log::ConstraintKind kind = toLogKind(c.kind);
  emitter_->constraint(kind, log::ConstraintAction::Created,
                       static_cast<std::uint32_t>(constraints_.size() - 1), std::move(content), std::move(vertices),
                       c.cause);
  return true;
}

bool TaskLayer::rejectTransition(int robot, const JointVector& q) { return rejected_.add(robot, q); }

std::optional<std::vector<TransitionConfig>> TaskLayer::resampleTransitions(const TaskPlan& plan,
                                                                            const Deadline& deadline) {
  log::PhaseTimer timer(*emitter_, log::Phase::TaskConflictDetection);
  TaskConflictDetector detector(sampler_, space_, graph_, rng_, params_.conflicts);
  detector.avoid(rejected_);
  TaskConflictResult conflicts = detector.detect(plan, deadline);
  if (!conflicts.feasible()) return std::nullopt;
  return std::move(conflicts.transitions);
}

void TaskLayer::restart(const std::string& why) {
  for (const TaskConstraint& c : constraints_.removeAll())
    emitter_->constraint(toLogKind(c.kind), log::ConstraintAction::Lifted, 0, why, {}, c.cause);
  rejected_ = RejectedConfigurations();
  motion_failures_.clear();
  ban_lifts_ = 0;
  ++restarts_;
  rng_ = Rng(Rng::derive(seed_, 11 + 1000 * static_cast<std::uint64_t>(restarts_)));
}

TaskLayer::Lifted TaskLayer::liftTemporaryConstraints(const std::string& why) {
  Lifted out;
  for (const TaskConstraint& c : constraints_.removeTemporary()) {
    emitter_->constraint(toLogKind(c.kind), log::ConstraintAction::Lifted,
                         0, why, {}, c.cause);
    out.any = true;
    out.motion = out.motion || c.from_motion;
  }
  return out;
}

void TaskLayer::expireTemporaryConstraints() {
  for (const TaskConstraint& c : constraints_.expireTemporary())
    emitter_->constraint(toLogKind(c.kind), log::ConstraintAction::Lifted,
                         0, "lifted after " + std::to_string(motion_failures_[banKey(c)]) + " task queries", {},
                         c.cause);
}

// Task space expansion: an extra stable pose ("move-out" state) for `object`, on a support surface
// near a robot that can take it from its start. Three passes of kMoveOutAttempts samples per robot:
// (1) a pose the robot can carry the object to with a grasp it takes it with, clear of every known
// object location; (2) a pose it can grasp with some grasp, clear of every known location; (3) the
// same, clear of the anchored locations (starts and goals) alone. Overlapping extra poses are
// resampleable: task conflict detection resamples them if both are ever occupied at once.
bool TaskLayer::expand(int object, const std::string& reason) {
  if (space_.extraLocationCount(object) >= params_.max_extra_locations_per_object) return false;
  const Scene& scene = *scene_;
  const std::vector<int> robots = robotsThatTake(object);
  std::vector<PlacementRegion> regions;
  for (const SceneSurface& surface : scene.surfaces) regions.emplace_back(surface);
  for (const MoveOutRule rule : {MoveOutRule{true, true}, MoveOutRule{false, true}, MoveOutRule{false, false}})
    for (int attempt = 0; attempt < kMoveOutAttempts; ++attempt)
      for (int r : robots) {
        if (rule.one_grasp && !params_.move_out_one_grasp) break;
        int s = -1;
        const auto pose = sampleMoveOut(object, r, rule, regions, s);
        if (!pose) continue;
        const int index = space_.addExtraLocation(object, *pose, s);
        const Vec3 p = pose->translation();
        emitter_->taskSpaceExpansion(static_cast<std::uint32_t>(object), scene.objects[object].id,
                                     space_.locationLabel(object, index) + " at (" + std::to_string(p.x()) + ", " +
                                         std::to_string(p.y()) + ", " + std::to_string(p.z()) + ") on " +
                                         scene.surfaces[s].id,
                                     reason);
        return true;
      }
  return false;
}

std::vector<int> TaskLayer::robotsThatTake(int object) {
  const Scene& scene = *scene_;
  const Pose& start = space_.location(object, space_.startLocation(object)).X_WO;
  std::vector<int> robots;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r)
    if (scene.robots[r].hasCapability("grasp") &&
        (reachability_.canGrasp(r, object, start, GraspClass::kTop) ||
         reachability_.canGrasp(r, object, start, GraspClass::kSide)))
      robots.push_back(r);
  return robots;
}

// One sample on a random support surface (near the base of an arm), kept if it passes `rule`.
std::optional<Pose> TaskLayer::sampleMoveOut(int object, int r, MoveOutRule rule,
                                             const std::vector<PlacementRegion>& regions, int& surface) {
  const Scene& scene = *scene_;
  const SceneObject& obj = scene.objects[object];
  surface = static_cast<int>(rng_.integer(0, static_cast<std::int64_t>(regions.size()) - 1));
  const PlacementRegion& region = regions[surface];
  const bool arm = scene.robots[r].model->kinematics == KinematicsKind::kUrDh;
  const auto pose = arm ? region.sampleNear(obj.shape, scene.robots[r].X_WB.translation(), kMoveOutRadius, rng_, 4)
                        : region.sample(obj.shape, rng_, 4);
  if (!pose) return std::nullopt;
  for (int o = 0; o < space_.objectCount(); ++o)
    for (const ObjectLocation& l : space_.locations(o))
      if ((rule.clear_of_extras || !l.resampleable) && (l.X_WO.translation() - pose->translation()).norm() < kMoveOutSpacing)
        return std::nullopt;
  if (objectInCollision(sampler_.world(), sampler_.context(), object, *pose, ObjectLayout::empty(scene)))
    return std::nullopt;
  if (!reachability_.canGrasp(r, object, *pose, GraspClass::kTop) &&
      !reachability_.canGrasp(r, object, *pose, GraspClass::kSide))
    return std::nullopt;
  const Pose& start = space_.location(object, space_.startLocation(object)).X_WO;
  if (rule.one_grasp && !movesOutWithOneGrasp(r, object, start, *pose)) return std::nullopt;
  return pose;
}

// A move-out pose serves only if robot r can carry the object there from its start with one grasp:
// some grasp that r can take at the start (the grasps task conflict detection tries) also holds the
// object, statically free, at the new pose. A side grasp out of a shelf cubby often has no such twin
// on a table, and a pose that only some other grasp reaches is a move-out that no chain can use.
bool TaskLayer::movesOutWithOneGrasp(int robot, int object, const Pose& from, const Pose& to) {
  const TaskConflictParams& p = params_.conflicts;
  for (GraspClass g : {GraspClass::kTop, GraspClass::kSide})
    for (const GraspConfig& gc : sampler_.graspConfigs(robot, object, from, g, p.grasp_candidates, p.prefer_free_approach))
      if (!sampler_.holdConfigs(robot, object, to, gc.X_TO, 1).empty()) return true;
  return false;
}

// The query failed under constraints: the objects that block others where they rest get a move-out
// state (paper: the constraints contradict each other; expand the task space).
std::vector<int> TaskLayer::objectsToExpandAfterFailure() const {
  std::vector<int> out;
  const TaskGraph& g = graph_.graph();
  for (const TaskConstraint& c : constraints_.all()) {
    if (c.kind == TaskConstraint::Kind::kInteraction) continue;
    const TaskElement& pre = g.property(c.pre);
    if (pre.kind != ElementKind::kObjectAt || space_.isFixed(pre.object)) continue;
    if (space_.extraLocationCount(pre.object) >= params_.max_extra_locations_per_object) continue;
    if (std::find(out.begin(), out.end(), pre.object) == out.end()) out.push_back(pre.object);
  }
  return out;
}

bool TaskLayer::holdsTemporaryMotionBans() const {
  const auto& all = constraints_.all();
  return std::any_of(all.begin(), all.end(), [](const TaskConstraint& c) { return c.temporary && c.from_motion; });
}

bool TaskLayer::expandAfterFailure(const TaskQueryResult& query) {
  if (query.unroutable_object >= 0) return false;
  bool expanded = false;
  for (int o : objectsToExpandAfterFailure())
    expanded = expand(o, std::string("task query ") + std::string(toString(query.status)) +
                             " under the task constraints") || expanded;
  if (expanded) rebuild();
  return expanded;
}

// A motion failure bans its hyperarc for some queries, not for ever (paper: the failed hyperarc is not
// removed): with no schedule around it, the same hyperarcs go back to the motion layer (which then
// searches harder: motion_bans_lifted), or to task conflict detection.
bool TaskLayer::liftAfterFailure(TaskLayerResult& result) {
  if (ban_lifts_ >= params_.max_ban_lifts) return false;
  const Lifted lifted = liftTemporaryConstraints("no schedule avoids the temporary bans");
  if (!lifted.any) return false;
  ++ban_lifts_;
  result.motion_bans_lifted = result.motion_bans_lifted || lifted.motion;
  return true;
}

TaskQueryObserver TaskLayer::queryObserver() {
  TaskQueryObserver observer;
  if (emitter_->enabled()) {
    observer.onVertex = [this](const ExtendedVertex& v) {
      ++extended_vertices_;
      emitter_->vertex(log::Layer::TaskExtended, static_cast<std::uint32_t>(extended_vertices_ - 1),
                       graph_.label(v.vertex, space_));
    };
    observer.onHyperarc = [this](const ExtendedHyperarc& a) {
      ++extended_hyperarcs_;
      emitter_->hyperarcOf(log::Layer::TaskExtended, taskArcTypeName(graph_.graph().property(a.hyperarc).type),
                           static_cast<std::uint32_t>(extended_hyperarcs_ - 1), a.produced, a.consumed);
    };
  } else {
    observer.onVertex = [this](const ExtendedVertex&) { ++extended_vertices_; };
    observer.onHyperarc = [this](const ExtendedHyperarc&) { ++extended_hyperarcs_; };
  }
  return observer;
}

// What comes first after a failed query. Mostly the task space grows (the constraints contradict each
// other). But a query that ran out of budget while motion bans held proves nothing, and a larger task
// space makes the next one harder still: the bans are lifted first. An object that the interaction
// constraints left without any route gets none from another object's move-out state: only lifting can
// help it. Without progress, `result` says why the layer is infeasible.
bool TaskLayer::recoverFromFailedQuery(const TaskQueryResult& query, TaskLayerResult& result) {
  const bool lift_first =
      query.unroutable_object >= 0 || (query.status == HyperpathStatus::kBudget && holdsTemporaryMotionBans());
  const bool progress = lift_first ? liftAfterFailure(result) || expandAfterFailure(query)
                                   : expandAfterFailure(query) || liftAfterFailure(result);
  if (progress) return true;
  result.status = TaskLayerStatus::kInfeasible;
  const auto& all = constraints_.all();
  result.no_route_in_task_hypergraph =
      query.unroutable_object >= 0 && std::none_of(all.begin(), all.end(), [](const TaskConstraint& c) {
        return c.kind == TaskConstraint::Kind::kInteraction;
      });
  result.reason = std::string("task query ") + std::string(toString(query.status)) + " with " +
                  std::to_string(constraints_.size()) + " task constraints" +
                  (query.unroutable_object < 0
                       ? std::string()
                       : ": " + scene_->objects[query.unroutable_object].id + " has no route to its goal");
  return false;
}

// Task conflicts found: their constraints, expansions and resampled locations. Returns the progress
// made (0: the same conflicts again with nothing new).
int TaskLayer::applyConflicts(const TaskConflictResult& conflicts) {
  int progress = conflicts.resampled;
  if (conflicts.move_outs_resampled > 0)
    emitter_->counter("move_out_resamples", move_outs_resampled_ += conflicts.move_outs_resampled);
  for (const TaskConstraint& c : conflicts.constraints) progress += addConstraint(c) ? 1 : 0;
  bool expanded = false;
  for (int o : conflicts.expand_objects) expanded = expand(o, "blocks another object where it must end") || expanded;
  if (expanded) {
    ++progress;
    rebuild();
  }
  return progress;
}

TaskLayerResult TaskLayer::plan(const Deadline& deadline) {
  TaskLayerResult result;
  rebuild();
  TaskConflictDetector detector(sampler_, space_, graph_, rng_, params_.conflicts);
  detector.avoid(rejected_);
  const TaskQueryObserver observer = queryObserver();

  for (int iteration = 0; iteration < params_.max_iterations; ++iteration) {
    if (deadline.expired()) {
      result.status = TaskLayerStatus::kTimeout;
      return result;
    }
    ++queries_;
    TaskQueryResult query;
    {
      log::PhaseTimer timer(*emitter_, log::Phase::TaskQuery);
      query = queryTaskPlan(graph_, space_, constraints_, params_.query, deadline, observer);
    }
    if (!query.found()) {
      if (query.status == HyperpathStatus::kDeadline) {
        result.status = TaskLayerStatus::kTimeout;
        return result;
      }
      if (recoverFromFailedQuery(query, result)) continue;
      return result;
    }
    TaskConflictResult conflicts;
    {
      log::PhaseTimer timer(*emitter_, log::Phase::TaskConflictDetection);
      conflicts = detector.detect(query.plan, deadline);
    }
    if (conflicts.interrupted) {
      result.status = TaskLayerStatus::kTimeout;
      return result;
    }
    emitter_->counter("collision_checks_task", static_cast<std::int64_t>(sampler_.context().counters().configuration_checks));
    if (conflicts.feasible()) {
      expireTemporaryConstraints();
      result.status = TaskLayerStatus::kFeasible;
      result.plan = std::move(query.plan);
      result.transitions = std::move(conflicts.transitions);
      return result;
    }
    const int progress = applyConflicts(conflicts);
    if (progress == 0) {
      result.status = TaskLayerStatus::kInfeasible;
      result.reason = "task conflicts repeat with no new constraint: " +
                      (conflicts.conflicts.empty() ? std::string("?") : conflicts.conflicts.front());
      return result;
    }
    emitter_->setIteration(emitter_->iteration() + 1);
  }
  result.status = TaskLayerStatus::kInfeasible;
  result.reason = "task layer iteration limit reached";
  return result;
}

}  // namespace dash
