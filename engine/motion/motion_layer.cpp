#include "engine/motion/motion_layer.h"

#include <cmath>

#include "engine/collision/collision_queries.h"
#include "engine/collision/region_queries.h"
#include "engine/collision/segment_queries.h"
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

double jointDistance(const JointVector& a, const JointVector& b) { return (a - b).cwiseAbs().sum(); }

/// Whether the joint-space segment q -> q_pre keeps the TCP near the straight line between their TCP
/// positions: a back-off is a Cartesian approach only then. An IK branch far from q in joint space
/// (a wrist flip near a singularity) passes the end-point checks but swings the arm through whatever
/// is next to the gripper, such as the partner of a handover.
bool staysOnApproachLine(const SceneRobot& r, const JointVector& q, const JointVector& q_pre) {
  const Vec3 a = forwardKinematics(*r.model, r.X_WB, q).X_WT.translation();
  const Vec3 b = forwardKinematics(*r.model, r.X_WB, q_pre).X_WT.translation();
  const double length = (b - a).norm();
  const double tolerance = 0.01 + 0.25 * length;
  constexpr int kSamples = 8;
  for (int i = 1; i < kSamples; ++i) {
    const double s = static_cast<double>(i) / kSamples;
    const Vec3 p = forwardKinematics(*r.model, r.X_WB, q + s * (q_pre - q)).X_WT.translation();
    if ((p - (a + s * (b - a))).norm() > tolerance) return false;
  }
  return true;
}

}  // namespace

std::string MotionLayer::collidingEnd(int robot, const JointVector& from, const JointVector& q_pre,
                                      const JointVector& q, const HeldObject& held, const ObjectLayout& layout) const {
  const std::pair<const char*, const JointVector*> ends[] = {{"start", &from}, {"approach start", &q_pre}, {"transition", &q}};
  for (const auto& [name, cfg] : ends) {
    CollisionReport report;
    if (robotInCollision(*world_, *context_, RobotState{robot, *cfg, held}, layout, &report))
      return std::string(name) + " configuration is in collision (" + describe(report, world_->scene()) + ")";
  }
  return {};
}

std::string MotionLayer::endInRegion(int robot, const JointVector& from, const JointVector& q_pre,
                                     const MotionContext& context) const {
  const std::pair<const char*, const JointVector*> ends[] = {{"start", &from}, {"approach start", &q_pre}};
  for (const auto& [name, cfg] : ends)
    if (robotEntersRegions(*world_, *context_, RobotState{robot, *cfg, context.held}, context.avoid))
      return std::string(name) + " configuration is inside a motion constraint's region";
  return {};
}

/// For people reading a failure: whether an end of the missing path is itself in collision.
std::string MotionLayer::whyNoPath(const std::string& colliding_end) {
  return colliding_end.empty() ? ": the roadmap found no way between valid ends" : ": the " + colliding_end;
}

namespace {

}  // namespace

MotionLayer::MotionLayer(const CollisionWorld& world, CollisionContext& context, log::EventEmitter& emitter,
                         MotionLayerParams params)
    : world_(&world),
      context_(&context),
      emitter_(&emitter),
      params_(params),
      graph_(emitter, [scene = &world.scene()](const lazy::MotionVertex& v) { return motionVertexLabel(*scene, v); }) {
  roadmaps_ = PerPlanningSpace<LazyRoadmap>(world.robotCount());
}

LazyRoadmap& MotionLayer::roadmap(int robot, bool holding) {
  auto& slot = roadmaps_.slot(robot, holding);
  if (!slot) {
    slot = std::make_unique<LazyRoadmap>(*world_, *context_, robot, params_.roadmap);
    slot->setEmitter(emitter_);
  }
  return *slot;
}

void MotionLayer::scaleBudget(double factor) {
  params_.roadmap.scale(factor);
  for (auto& r : roadmaps_)
    if (r) r->scaleBudget(factor);
}

std::size_t MotionLayer::roadmapVertices(int robot, bool holding) const {
  const auto& slot = roadmaps_.slot(robot, holding);
  return slot ? slot->vertexCount() : 0;
}

std::size_t MotionLayer::roadmapEdges(int robot, bool holding) const {
  const auto& slot = roadmaps_.slot(robot, holding);
  return slot ? slot->edgeCount() : 0;
}

std::size_t MotionLayer::roadmapVertices() const {
  std::size_t n = 0;
  for (const auto& r : roadmaps_) n += r ? r->vertexCount() : 0;
  return n;
}

std::size_t MotionLayer::roadmapEdges() const {
  std::size_t n = 0;
  for (const auto& r : roadmaps_) n += r ? r->edgeCount() : 0;
  return n;
}

std::optional<std::vector<JointVector>> MotionLayer::connect(int robot, const JointVector& from, const JointVector& to,
                                                             const MotionContext& motion, const Deadline& deadline) {
  if (jointDistance(from, to) < 1e-9) return std::vector<JointVector>{from};
  // Cheapest check first: the straight segment.
  if (params_.straight_first && motion.parked.empty() &&
      !segmentInCollision(*world_, *context_, RobotState{robot, from, motion.held}, to, motion.layout) &&
      !segmentEntersRegions(*world_, *context_, RobotState{robot, from, motion.held}, to, motion.avoid))
    return std::vector<JointVector>{from, to};
  return roadmap(robot, motion.held.holding()).query(from, to, motion, deadline);
}

std::optional<JointVector> MotionLayer::backedOff(int robot, const JointVector& q, const HeldObject& held,
                                                  const ObjectLayout& layout, const std::optional<Vec3>& direction_W,
                                                  double distance, const std::optional<RobotState>& partner) {
  const SceneRobot& r = world_->scene().robots[robot];
  const Pose X_WT = forwardKinematics(*r.model, r.X_WB, q).X_WT;
  const double d = distance > 0.0 ? distance : params_.approach_distance;
  Pose X_WTpre = X_WT * makePose(Vec3(0, 0, -d));
  if (direction_W) X_WTpre = makePose(d * direction_W->normalized()) * X_WT;
  // Sideways approaches also rise a little: an object resting on a pedestal or board touches it, and
  // the joint-space segment would graze it on the way out. With a handover partner's hand next to the
  // object the rise may sweep through it; then the straight line is tried too.
  const Vec3 axis_W = direction_W ? direction_W->normalized() : Vec3(X_WT.linear().col(2));
  std::vector<Pose> targets;
  if (std::abs(axis_W.z()) < 0.7) targets.push_back(makePose(Vec3(0, 0, params_.side_lift)) * X_WTpre);
  if (targets.empty() || partner) targets.push_back(X_WTpre);
  for (const Pose& target : targets) {
    std::optional<JointVector> best;
    for (const JointVector& cand : inverseKinematics(*r.model, r.X_WB, target)) {
      if (best && jointDistance(cand, q) >= jointDistance(*best, q)) continue;
      if (!staysOnApproachLine(r, q, cand)) continue;
      const RobotState state{robot, cand, held};
      if (robotInCollision(*world_, *context_, state, layout)) continue;
      if (segmentInCollision(*world_, *context_, state, q, layout)) continue;
      if (!held.holding() && gripperEntersContactBox(*world_, *context_, robot, cand, q, layout)) continue;
      if (partner) {
        const RobotMotion motions[2] = {{state, q}, {*partner, partner->q}};
        if (motionsInCollision(*world_, *context_, motions, ObjectLayout::empty(world_->scene()), nullptr,
                               {CheckScope::kStaticOnly}))
          continue;
      }
      best = cand;
    }
    if (best) return best;
  }
  return std::nullopt;
}

std::optional<JointVector> MotionLayer::farthestBackOff(int robot, const JointVector& q, const HeldObject& held,
                                                        const ObjectLayout& layout) {
  for (auto d = params_.deep_approach_distances.rbegin(); d != params_.deep_approach_distances.rend(); ++d)
    if (auto q_back = backedOff(robot, q, held, layout, {}, *d)) return q_back;
  return std::nullopt;
}

MotionLayerResult MotionLayer::plan(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                    const TaskSpace& space, const Deadline& deadline) {
  MotionLayerResult result = trace(plan, transitions, space, deadline);
  if (result.status != MotionStatus::kTimeout) recordInHypergraph(plan, transitions, space, result, deadline);
  return result;
}

MotionLayerResult MotionLayer::trace(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                     const TaskSpace& space, const Deadline& deadline) {
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  MotionLayerResult result;
  result.robots.resize(static_cast<std::size_t>(robots));
  const std::vector<ObjectLayout> layouts = restingAlong(plan, space).layouts;
  std::vector<JointVector> at(static_cast<std::size_t>(robots));
  // Whether each robot's last retreat backed off along its own approach axis (so may back off farther).
  std::vector<bool> own_retreat(static_cast<std::size_t>(robots), false);
  // Out of a cubby: the robot's last retreat, if along its own axis, backs off as far as it validly can
  // and the robot continues from there.
  auto backOutOfLastRetreat = [&](int r) {
    if (!own_retreat[r] || result.robots[r].visits.empty()) return false;
    StepVisit& last = result.robots[r].visits.back();
    const auto post = farthestBackOff(r, last.q, last.held_after, layouts[last.step + 1]);
    if (!post) return false;
    last.q_post = at[r] = *post;
    return true;
  };
  for (int r = 0; r < robots; ++r) {
    at[r] = scene.robots[r].home;
  }

  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    const TaskArc& a = plan.steps[k].action;
    const TransitionConfig& tc = transitions[k];
    bool giver_backs_off = true;
    JointVector giver_q_post = tc.q;
    Vec3 giver_approach_W = Vec3::UnitZ();
    for (int role = 0; role < (a.type == TaskArcType::kHandover ? 2 : 1); ++role) {
      if (deadline.expired()) {
        result.status = MotionStatus::kTimeout;
        return result;
      }
      // H_M's anchors for this visit (approach start and retreat end around the transition
      // configuration) are its construction; finding and validating the moves between them, roadmap
      // growth included (Lazy-PRM grows while it queries), is the motion query.
      log::PhaseTimer construction(*emitter_, log::Phase::MotionConstruction);
      const bool receiver = role == 1;
      const int r = receiver ? a.robot2 : a.robot;
      const Roles held = heldAround(a, tc, receiver);
      StepVisit visit;
      visit.step = k;
      visit.receiver = receiver;
      visit.q = receiver ? tc.q2 : tc.q;
      visit.held_before = held.before;
      visit.held_after = held.after;
      const bool giver = a.type == TaskArcType::kHandover && !receiver;
      // In a handover the partner stands at its transition configuration while this robot approaches
      // (the giver, holding the object) and while this robot retreats (giver first: the receiver holding
      // the object; then the receiver: the giver where its retreat ended, empty-handed).
      std::optional<RobotState> partner_before, partner_after;
      if (a.type == TaskArcType::kHandover) {
        if (receiver) {
          partner_before = RobotState{a.robot, tc.q, HeldObject{a.object, tc.X_TO}};
          partner_after = RobotState{a.robot, giver_q_post, HeldObject{}};
        } else {
          partner_after = RobotState{a.robot2, tc.q2, HeldObject{a.object, tc.X_TO2}};
        }
      }
      // The giver brings the object straight to the handover pose; everyone else approaches along the
      // TCP axis so that fingers slide around the object instead of sweeping through it.
      visit.q_pre =
          giver ? visit.q : backedOff(r, visit.q, held.before, layouts[k], {}, 0.0, partner_before).value_or(visit.q);
      const bool own_axis = !(receiver && !giver_backs_off);
      if (!own_axis) {
        // The giver cannot back off (its approach axis leads out of reach): the receiver pulls the
        // object out of the giver's open fingers along the giver's approach axis instead.
        visit.q_post =
            backedOff(r, visit.q, held.after, layouts[k + 1], giver_approach_W, 0.0, partner_after).value_or(visit.q);
      } else {
        visit.q_post = backedOff(r, visit.q, held.after, layouts[k + 1], {}, 0.0, partner_after).value_or(visit.q);
      }
      if (giver) {
        giver_q_post = visit.q_post;
        giver_backs_off = (visit.q_post - visit.q).cwiseAbs().maxCoeff() > 1e-12;
        const SceneRobot& sr = scene.robots[r];
        giver_approach_W = forwardKinematics(*sr.model, sr.X_WB, visit.q).X_WT.linear().col(2);
      }
      construction.stop();
      log::PhaseTimer query(*emitter_, log::Phase::MotionQuery);
      const MotionContext context{held.before, layouts[k], {},
                                  constraints_ ? constraints_->regionsFor(plan, r, k, visit.q) : std::vector<Aabb>{}};
      auto transit = connect(r, at[r], visit.q_pre, context, deadline);
      // Local refinement: deep in a shelf cubby the short approach and retreat leave the arm where a
      // roadmap hardly reaches. Back off farther along the same axes (the straight segment to the
      // transition is checked) and connect again.
      // The farthest valid back-off is tried (the farther out, the easier the roadmap's part), with a
      // single roadmap query: a failing query costs its whole budget.
      if (!transit && !deadline.expired()) {
        bool changed = false;
        if (!giver)
          if (auto pre = farthestBackOff(r, visit.q, held.before, layouts[k])) {
            visit.q_pre = *pre;
            changed = true;
          }
        if (backOutOfLastRetreat(r)) changed = true;
        if (changed) transit = connect(r, at[r], visit.q_pre, context, deadline);
      }
      // Global sampling: trees grown from both ends.
      if (!transit && params_.global_sampling && !deadline.expired())
        transit = roadmap(r, held.before.holding()).queryTrees(at[r], visit.q_pre, context, deadline);
      if (!transit) {
        result.status = deadline.expired() ? MotionStatus::kTimeout : MotionStatus::kFailed;
        result.failed_step = k;
        result.failed_robot = r;
        result.failed_q = visit.q;
        const std::string colliding = collidingEnd(r, at[r], visit.q_pre, visit.q, held.before, layouts[k]);
        const std::string in_region = endInRegion(r, at[r], visit.q_pre, context);
        result.ends_free = colliding.empty();
        result.reason = "no path for " + scene.robots[r].id + " to step " + std::to_string(k) + " (" +
                        describeStep(plan.steps[k], space) + ")" + whyNoPath(colliding.empty() ? in_region : colliding);
        return result;
      }
      visit.transit = *transit;
      at[r] = visit.q_post;
      own_retreat[r] = own_axis;
      result.robots[r].visits.push_back(std::move(visit));
    }
  }
  if (scene.end_at_home) {
    log::PhaseTimer query(*emitter_, log::Phase::MotionQuery);
    for (int r = 0; r < robots; ++r) {
      const MotionContext context{{}, layouts.back(), {}};
      auto home = connect(r, at[r], scene.robots[r].home, context, deadline);
      // As for a transit: out of a cubby, the last retreat backs off farther along its axis.
      if (!home && !deadline.expired() && backOutOfLastRetreat(r))
        home = connect(r, at[r], scene.robots[r].home, context, deadline);
      if (!home && params_.global_sampling && !deadline.expired())
        home = roadmap(r, false).queryTrees(at[r], scene.robots[r].home, context, deadline);
      if (!home) {
        result.status = deadline.expired() ? MotionStatus::kTimeout : MotionStatus::kFailed;
        result.reason = "no path home for " + scene.robots[r].id +
                        whyNoPath(collidingEnd(r, at[r], scene.robots[r].home, scene.robots[r].home, {}, layouts.back()));
        return result;
      }
      result.robots[r].home_path = *home;
    }
  }
  emitter_->counter("roadmap_vertices", static_cast<std::int64_t>(roadmapVertices()));
  emitter_->counter("roadmap_edges", static_cast<std::int64_t>(roadmapEdges()));
  result.status = MotionStatus::kOk;
  return result;
}

}  // namespace dash
