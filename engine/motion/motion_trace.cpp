// MotionLayer's motion query along the unvalidated schedule (paper, "Query (Motion-extended
// Hypergraph)"): the moves between the transition configurations, found and validated lazily in
// schedule order, each in the motion context of its moment (what rests where, what the robot holds, the
// regions of the motion constraints on its history). When a move is missing: local refinement first
// (farther back-offs along the same approach axes), then global sampling. A small object whose methods
// are the query's steps: one robot's part in one task step (visit), the way home (home).
#include <cmath>
#include <optional>
#include <utility>

#include "engine/motion/motion_layer.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

struct Roles {
  HeldObject before;
  HeldObject after;
};

Roles heldAround(const TaskArc& a, const TransitionConfig& tc, bool receiver) {
  switch (a.type) {
    case TaskArcType::kPick:
      return {{}, {a.object, tc.X_TO}};
    case TaskArcType::kPlace:
      return {{a.object, tc.X_TO}, {}};
    case TaskArcType::kHandover:
      return receiver ? Roles{{}, {a.object, tc.X_TO2}} : Roles{{a.object, tc.X_TO}, {}};
    default:
      return {};
  }
}

/// What the giver of a handover did, for the receiver that follows it in the same step.
struct GiverState {
  bool backs_off = true;
  JointVector q_post;
  Vec3 approach_W = Vec3::UnitZ();
};

/// In a handover the partner stands at its transition configuration while this robot approaches (the
/// giver, holding the object) and while this robot retreats (giver first: the receiver holding the
/// object; then the receiver: the giver where its retreat ended, empty-handed). Before and after.
std::pair<std::optional<RobotState>, std::optional<RobotState>> partnersAround(const TaskArc& a,
                                                                               const TransitionConfig& tc,
                                                                               bool receiver, const GiverState& giver) {
  if (a.type != TaskArcType::kHandover) return {};
  if (receiver)
    return {RobotState{a.robot, tc.q, HeldObject{a.object, tc.X_TO}}, RobotState{a.robot, giver.q_post, HeldObject{}}};
  return {std::nullopt, RobotState{a.robot2, tc.q2, HeldObject{a.object, tc.X_TO2}}};
}

}  // namespace

struct MotionTrace {
  MotionLayer& layer;
  const TaskPlan& plan;
  const std::vector<TransitionConfig>& transitions;
  const TaskSpace& space;
  const Deadline& deadline;
  const Scene& scene = space.scene();
  const std::vector<ObjectLayout> layouts = restingAlong(plan, space).layouts;
  MotionLayerResult result;
  std::vector<JointVector> at;  ///< where each robot stands now
  /// Whether each robot's last retreat backed off along its own approach axis (so may back off farther).
  std::vector<bool> own_retreat;

  MotionLayerResult run();
  /// One robot's part in step k (role 1: a handover's receiver); false when it stopped `result`.
  bool visit(int k, int role, GiverState& giver);
  /// Every robot back home (when the scene wants it); false when it stopped `result`.
  bool home();
  /// Out of a cubby: robot r's last retreat, if along its own axis, backs off as far as it validly can
  /// and the robot continues from there.
  bool backOutOfLastRetreat(int r);
  /// result as failed (or timed out) at step k for robot r.
  void fail(int k, int r, const JointVector& q, const std::string& why, bool ends_free);
};

MotionLayerResult MotionTrace::run() {
  const int robots = static_cast<int>(scene.robots.size());
  result.robots.resize(static_cast<std::size_t>(robots));
  own_retreat.assign(static_cast<std::size_t>(robots), false);
  for (int r = 0; r < robots; ++r) at.push_back(scene.robots[r].home);
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    GiverState giver;
    giver.q_post = transitions[k].q;
    for (int role = 0; role < (plan.steps[k].action.type == TaskArcType::kHandover ? 2 : 1); ++role)
      if (!visit(k, role, giver)) return std::move(result);
  }
  if (scene.end_at_home && !home()) return std::move(result);
  layer.emitter_->counter("roadmap_vertices", static_cast<std::int64_t>(layer.roadmapVertices()));
  layer.emitter_->counter("roadmap_edges", static_cast<std::int64_t>(layer.roadmapEdges()));
  result.status = MotionStatus::kOk;
  return std::move(result);
}

bool MotionTrace::backOutOfLastRetreat(int r) {
  if (!own_retreat[r] || result.robots[r].visits.empty()) return false;
  StepVisit& last = result.robots[r].visits.back();
  const auto post = layer.farthestBackOff(r, last.q, last.held_after, layouts[last.step + 1]);
  if (!post) return false;
  setRetreat(last, post);
  at[r] = last.q_post;
  return true;
}

void MotionTrace::fail(int k, int r, const JointVector& q, const std::string& why, bool ends_free) {
  result.status = deadline.expired() ? MotionStatus::kTimeout : MotionStatus::kFailed;
  result.failed_step = k;
  result.failed_robot = r;
  result.failed_q = q;
  result.ends_free = ends_free;
  result.reason = why;
}

bool MotionTrace::visit(int k, int role, GiverState& giver) {
  const TaskArc& a = plan.steps[k].action;
  const TransitionConfig& tc = transitions[k];
  if (deadline.expired()) {
    result.status = MotionStatus::kTimeout;
    return false;
  }
  // H_M's anchors for this visit (approach start and retreat end around the transition configuration)
  // are its construction; finding and validating the moves between them, roadmap growth included
  // (Lazy-PRM grows while it queries), is the motion query.
  log::PhaseTimer construction(*layer.emitter_, log::Phase::MotionConstruction);
  const bool receiver = role == 1;
  const int r = receiver ? a.robot2 : a.robot;
  const Roles held = heldAround(a, tc, receiver);
  StepVisit v;
  v.step = k;
  v.receiver = receiver;
  v.q = receiver ? tc.q2 : tc.q;
  v.held_before = held.before;
  v.held_after = held.after;
  const bool is_giver = a.type == TaskArcType::kHandover && !receiver;
  const auto [partner_before, partner_after] = partnersAround(a, tc, receiver, giver);
  // The giver brings the object straight to the handover pose; everyone else approaches along the TCP
  // axis so that fingers slide around the object instead of sweeping through it.
  setApproach(v, is_giver ? std::nullopt : layer.backedOff(r, v.q, held.before, layouts[k], {}, 0.0, partner_before));
  // The giver cannot back off (its approach axis leads out of reach): the receiver pulls the object out
  // of the giver's open fingers along the giver's approach axis instead.
  const bool own_axis = !(receiver && !giver.backs_off);
  const std::optional<Vec3> retreat_axis = own_axis ? std::optional<Vec3>() : giver.approach_W;
  setRetreat(v, layer.backedOff(r, v.q, held.after, layouts[k + 1], retreat_axis, 0.0, partner_after));
  if (is_giver) {
    giver.q_post = v.q_post;
    giver.backs_off = (v.q_post - v.q).cwiseAbs().maxCoeff() > 1e-12;
    const SceneRobot& sr = scene.robots[r];
    giver.approach_W = forwardKinematics(*sr.model, sr.X_WB, v.q).X_WT.linear().col(2);
  }
  construction.stop();
  log::PhaseTimer query(*layer.emitter_, log::Phase::MotionQuery);
  const MotionContext context{held.before, layouts[k], {},
                              layer.constraints_ ? layer.constraints_->regionsFor(plan, r, k, v.q) : std::vector<Aabb>{}};
  auto transit = layer.connect(r, at[r], v.q_pre, context, deadline);
  // Local refinement: deep in a shelf cubby the short approach and retreat leave the arm where a roadmap
  // hardly reaches. Back off farther along the same axes (the straight segment to the transition is
  // checked) and connect again: the farthest valid back-off (the farther out, the easier the roadmap's
  // part), with a single roadmap query (a failing query costs its whole budget).
  if (!transit && !deadline.expired()) {
    bool changed = false;
    if (!is_giver)
      if (auto pre = layer.farthestBackOff(r, v.q, held.before, layouts[k])) {
        setApproach(v, pre);
        changed = true;
      }
    if (backOutOfLastRetreat(r)) changed = true;
    if (changed) transit = layer.connect(r, at[r], v.q_pre, context, deadline);
  }
  // Global sampling: trees grown from both ends.
  if (!transit && layer.params_.global_sampling && !deadline.expired())
    transit = layer.roadmap(r, held.before.holding()).queryTrees(at[r], v.q_pre, context, deadline);
  if (!transit) {
    const std::string colliding = layer.collidingEnd(r, at[r], v.q_pre, v.q, held.before, layouts[k]);
    const std::string in_region = layer.endInRegion(r, at[r], v.q_pre, context);
    fail(k, r, v.q,
         "no path for " + scene.robots[r].id + " to step " + std::to_string(k) + " (" + describeStep(plan.steps[k], space) +
             ")" + MotionLayer::whyNoPath(colliding.empty() ? in_region : colliding),
         colliding.empty());
    return false;
  }
  v.transit = *transit;
  at[r] = v.q_post;
  own_retreat[r] = own_axis;
  result.robots[r].visits.push_back(std::move(v));
  return true;
}

bool MotionTrace::home() {
  log::PhaseTimer query(*layer.emitter_, log::Phase::MotionQuery);
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    const MotionContext context{{}, layouts.back(), {}};
    const JointVector& q_home = scene.robots[r].home;
    auto path = layer.connect(r, at[r], q_home, context, deadline);
    // As for a transit: out of a cubby, the last retreat backs off farther along its axis.
    if (!path && !deadline.expired() && backOutOfLastRetreat(r)) path = layer.connect(r, at[r], q_home, context, deadline);
    if (!path && layer.params_.global_sampling && !deadline.expired())
      path = layer.roadmap(r, false).queryTrees(at[r], q_home, context, deadline);
    if (!path) {
      result.status = deadline.expired() ? MotionStatus::kTimeout : MotionStatus::kFailed;
      result.reason = "no path home for " + scene.robots[r].id +
                      MotionLayer::whyNoPath(layer.collidingEnd(r, at[r], q_home, q_home, {}, layouts.back()));
      return false;
    }
    result.robots[r].home_path = *path;
  }
  return true;
}

MotionLayerResult MotionLayer::trace(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                     const TaskSpace& space, const Deadline& deadline) {
  return MotionTrace{*this, plan, transitions, space, deadline}.run();
}

}  // namespace dash
