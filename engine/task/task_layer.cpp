#include "engine/task/task_layer.h"

#include <algorithm>

namespace dash {

namespace {
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
      reachability_(sampler_, params_.reachability),
      move_outs_(space_, sampler_, reachability_, params_.conflicts, params_.move_out_one_grasp) {
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
  detector.resampleMoveOutsWith(move_outs_);
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

// Task space expansion: an extra stable pose ("move-out" state) for `object` (MoveOutSampler).
bool TaskLayer::expand(int object, const std::string& reason) {
  if (space_.extraLocationCount(object) >= params_.max_extra_locations_per_object) return false;
  const std::optional<MoveOutPose> found = move_outs_.forExpansion(object, rng_);
  if (!found) return false;
  const int index = space_.addExtraLocation(object, found->X_WO, found->surface);
  const Vec3 p = found->X_WO.translation();
  emitter_->taskSpaceExpansion(static_cast<std::uint32_t>(object), scene_->objects[object].id,
                               space_.locationLabel(object, index) + " at (" + std::to_string(p.x()) + ", " +
                                   std::to_string(p.y()) + ", " + std::to_string(p.z()) + ") on " +
                                   scene_->surfaces[found->surface].id,
                               reason);
  return true;
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
  detector.resampleMoveOutsWith(move_outs_);
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
