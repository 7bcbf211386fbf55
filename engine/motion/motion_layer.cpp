#include "engine/motion/motion_layer.h"

#include <algorithm>
#include <cmath>

#include "engine/collision/collision_queries.h"
#include "engine/collision/region_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/robots/cartesian_path.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

double jointDistance(const JointVector& a, const JointVector& b) { return (a - b).cwiseAbs().sum(); }

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

bool MotionLayer::fixedEndsEnter(const MotionLayerResult& motions, int robot, int step,
                                 const std::vector<Aabb>& region) const {
  if (robot < 0 || robot >= static_cast<int>(motions.robots.size())) return false;
  const auto& visits = motions.robots[static_cast<std::size_t>(robot)].visits;
  const auto visit = std::find_if(visits.begin(), visits.end(), [&](const StepVisit& v) { return v.step == step; });
  if (visit == visits.end() || visit->transit.empty()) return false;
  MotionContext ends;
  ends.held = visit->held_before;
  ends.avoid = region;
  return !endInRegion(robot, visit->transit.front(), visit->q_pre, ends).empty();
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
  // Sideways approaches also rise a little (backOffPose): an object resting on a pedestal or board
  // touches it. With a handover partner's hand next to the object the rise may sweep through it; then
  // the straight line is tried too.
  std::vector<Pose> targets{backOffPose(X_WT, d, params_.side_lift, direction_W)};
  if (partner && backsOffSideways(X_WT, direction_W)) targets.push_back(backOffPose(X_WT, d, 0.0, direction_W));
  for (const Pose& target : targets) {
    // The IK solutions nearest q first: the first whose straight line from q is free. One far from q
    // in joint space (a wrist flip near a singularity) has no Cartesian path from q at all.
    std::vector<JointVector> candidates = inverseKinematics(*r.model, r.X_WB, target);
    std::sort(candidates.begin(), candidates.end(),
              [&](const JointVector& a, const JointVector& b) { return jointDistance(a, q) < jointDistance(b, q); });
    for (const JointVector& cand : candidates) {
      // The path the visit will have (backOffPath of these ends: cartesianPath is deterministic).
      const std::optional<std::vector<JointVector>> path = backOffLine(*r.model, r.X_WB, q, cand);
      if (path && backOffFree(robot, *path, held, layout, partner)) return cand;
    }
  }
  return std::nullopt;
}

bool MotionLayer::backOffFree(int robot, const std::vector<JointVector>& path, const HeldObject& held,
                              const ObjectLayout& layout, const std::optional<RobotState>& partner) const {
  // The waypoints once each (q, the first, is the transition configuration: checked by its caller),
  // then the segments between them.
  for (std::size_t i = path.size(); i-- > 1;)
    if (robotInCollision(*world_, *context_, RobotState{robot, path[i], held}, layout)) return false;
  for (std::size_t i = path.size(); i-- > 1;) {
    const RobotState state{robot, path[i], held};
    if (segmentInCollision(*world_, *context_, state, path[i - 1], layout, nullptr, SegmentOptions{.check_endpoints = false}))
      return false;
    if (!held.holding() && gripperEntersContactBox(*world_, *context_, robot, path[i], path[i - 1], layout)) return false;
    if (partner) {
      const RobotMotion motions[2] = {{state, path[i - 1]}, {*partner, partner->q}};
      if (motionsInCollision(*world_, *context_, motions, ObjectLayout::empty(world_->scene()), nullptr,
                             {CheckScope::kStaticOnly}))
        return false;
    }
  }
  return true;
}

std::optional<JointVector> MotionLayer::farthestBackOff(int robot, const JointVector& q, const HeldObject& held,
                                                        const ObjectLayout& layout) {
  for (auto d = params_.deep_approach_distances.rbegin(); d != params_.deep_approach_distances.rend(); ++d)
    if (auto q_back = backedOff(robot, q, held, layout, {}, *d)) return q_back;
  return std::nullopt;
}

void setApproach(StepVisit& v, const std::optional<std::vector<JointVector>>& back_off) {
  v.approach = back_off ? std::vector<JointVector>(back_off->rbegin(), back_off->rend()) : std::vector<JointVector>{v.q};
  v.q_pre = v.approach.front();
}

void setRetreat(StepVisit& v, const std::optional<std::vector<JointVector>>& back_off) {
  v.retreat = back_off ? *back_off : std::vector<JointVector>{v.q};
  v.q_post = v.retreat.back();
}

void MotionLayer::setBackOffPaths(StepVisit& v, int robot) const {
  const SceneRobot& r = world_->scene().robots[robot];
  setApproach(v, backOffPath(*r.model, r.X_WB, v.q, v.q_pre));
  setRetreat(v, backOffPath(*r.model, r.X_WB, v.q, v.q_post));
}

}  // namespace dash
