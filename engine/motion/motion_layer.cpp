#include "engine/motion/motion_layer.h"

#include <cmath>

#include "engine/collision/collision_queries.h"
#include "engine/collision/region_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

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

}  // namespace dash
