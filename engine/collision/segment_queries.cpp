#include "engine/collision/segment_queries.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/collision/collision_internal.h"
#include "engine/core/check.h"

namespace dash {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Lever of the held object per joint: the TCP's lever plus the object's farthest point from the TCP
/// (revolute joints); a prismatic joint moves every point by exactly |dq|.
double heldDisplacement(const CollisionWorld& world, int r, const JointVector& dq_abs, const HeldObject& held) {
  const RobotGeometry& rg = world.robot(r);
  const bool revolute = rg.model->kinematics == KinematicsKind::kUrDh;
  double extent = 0.0;
  if (held.holding()) {
    const Vec3 half = 0.5 * world.scene().objects[at(held.object)].shape.size;
    extent = held.X_TO.translation().norm() + half.norm();
  }
  double d = 0.0;
  for (Eigen::Index i = 0; i < dq_abs.size(); ++i) d += dq_abs[i] * (rg.tcp_lever[i] + (revolute ? extent : 0.0));
  return d;
}

double bodyDisplacement(const RobotGeometry& rg, int b, const JointVector& dq_abs) {
  return dq_abs.dot(rg.body_lever[at(b)]);
}

Aabb grown(const Aabb& box, double margin) {
  return Aabb(box.min().array() - margin, box.max().array() + margin);
}

/// Swept boxes of robot r along q0 -> q1: per body into `swept`, the held object into `held_swept`;
/// returns the robot's whole swept box (bodies and held object). Leaves the robot posed at q1.
Aabb sweptBoxes(const CollisionWorld& world, CollisionContext& context, int r, const JointVector& q0,
                const JointVector& q1, const HeldObject& held, std::vector<Aabb>& swept, Aabb& held_swept) {
  const RobotGeometry& rg = world.robot(r);
  const auto& posed = context.scratch().robots[at(r)];
  const JointVector dq_abs = (q1 - q0).cwiseAbs();
  detail::poseRobot(world, context, r, q0, held);
  swept.assign(posed.body_aabb.begin(), posed.body_aabb.end());
  held_swept = posed.held_aabb;
  detail::poseRobot(world, context, r, q1, held);
  Aabb whole;
  whole.setEmpty();
  for (int b = 0; b < static_cast<int>(swept.size()); ++b) {
    swept[at(b)].extend(posed.body_aabb[at(b)]);
    swept[at(b)] = grown(swept[at(b)], 0.5 * bodyDisplacement(rg, b, dq_abs));
    whole.extend(swept[at(b)]);
  }
  if (held.holding()) {
    held_swept.extend(posed.held_aabb);
    held_swept = grown(held_swept, 0.5 * heldDisplacement(world, r, dq_abs, held));
    whole.extend(held_swept);
  }
  return whole;
}

/// Interior configurations k = 1 .. n-1 of n intervals, coarse to fine (each visited once).
template <class Visit>
bool forEachInteriorStep(int n, Visit visit) {
  int top = 1;
  while (top * 2 < n) top *= 2;
  for (int s = top; s >= 1; s /= 2) {
    for (int k = s; k < n; k += s) {
      if (s != top && (k / s) % 2 == 0) continue;
      if (visit(k)) return true;
    }
  }
  return false;
}

JointVector interpolate(const JointVector& q0, const JointVector& q1, double t) { return q0 + t * (q1 - q0); }

/// One robot's segment with the resting set already prepared. End points are checked only if asked.
bool robotSegment(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                  const JointVector& q_end, CollisionReport* report, const SegmentOptions& options) {
  const int r = start.robot;
  DASH_DEMAND(r >= 0 && r < world.robotCount());
  DASH_DEMAND_MSG(q_end.size() == start.q.size(), "segment end points differ in size");
  auto& s = context.scratch();
  const detail::CandidateView full = detail::fullCandidates(world, context, r, options.scope);
  auto check_at = [&](const JointVector& q, double fraction, const detail::CandidateView& view) {
    ++context.counters().configuration_checks;
    detail::poseRobot(world, context, r, q, start.held);
    if (!detail::checkPosedRobot(world, context, r, view, report)) return false;
    if (report != nullptr) report->segment_fraction = fraction;
    return true;
  };
  if (options.check_endpoints) {
    if (check_at(start.q, 0.0, full) || check_at(q_end, 1.0, full)) return true;
  }

  Aabb held_swept;
  const Aabb whole = sweptBoxes(world, context, r, start.q, q_end, start.held, s.swept_body, held_swept);
  const bool holding = start.held.holding();
  auto& c = s.candidates;
  c.obstacles.clear();
  c.held_obstacles.clear();
  c.objects.clear();
  c.self_pairs.clear();
  c.held_vs_bodies.clear();
  for (const int i : full.obstacles) {
    const Aabb& box = world.obstacles()[at(i)].aabb;
    if (!whole.intersects(box)) continue;
    if (std::any_of(s.swept_body.begin(), s.swept_body.end(), [&](const Aabb& b) { return b.intersects(box); })) {
      c.obstacles.push_back(i);
    }
  }
  if (holding) {
    for (const int i : full.held_obstacles) {
      if (held_swept.intersects(world.obstacles()[at(i)].aabb)) c.held_obstacles.push_back(i);
    }
    for (const int b : full.held_vs_bodies) {
      if (held_swept.intersects(s.swept_body[at(b)])) c.held_vs_bodies.push_back(b);
    }
  }
  for (const int j : full.objects) {
    const Aabb& box = s.object_aabb[at(j)];
    if (!whole.intersects(box)) continue;
    const bool near = (holding && held_swept.intersects(box)) ||
                      std::any_of(s.swept_body.begin(), s.swept_body.end(), [&](const Aabb& b) { return b.intersects(box); });
    if (near) c.objects.push_back(j);
  }
  for (const auto& pair : full.self_pairs) {
    if (s.swept_body[at(pair.first)].intersects(s.swept_body[at(pair.second)])) c.self_pairs.push_back(pair);
  }
  if (c.obstacles.empty() && c.held_obstacles.empty() && c.objects.empty() && c.self_pairs.empty() &&
      c.held_vs_bodies.empty()) {
    return false;  // nothing anywhere near the swept volume
  }
  const detail::CandidateView narrowed{c.obstacles, c.held_obstacles, c.objects, c.self_pairs, c.held_vs_bodies};
  const int n = segmentSteps(world, r, start.q, q_end, start.held, options.resolution);
  return forEachInteriorStep(n, [&](int k) {
    const double t = static_cast<double>(k) / n;
    return check_at(interpolate(start.q, q_end, t), t, narrowed);
  });
}

}  // namespace

double segmentDisplacementBound(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                                const HeldObject& held) {
  const RobotGeometry& rg = world.robot(robot);
  const JointVector dq_abs = (q1 - q0).cwiseAbs();
  double d = heldDisplacement(world, robot, dq_abs, held);  // includes the TCP itself
  for (int b = 0; b < static_cast<int>(rg.bodies.size()); ++b) d = std::max(d, bodyDisplacement(rg, b, dq_abs));
  return d;
}

int segmentSteps(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                 const HeldObject& held, double resolution) {
  DASH_DEMAND(resolution > 0.0);
  const double d = segmentDisplacementBound(world, robot, q0, q1, held);
  return std::max(1, static_cast<int>(std::ceil(d / resolution)));
}

bool segmentInCollision(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                        const JointVector& q_end, const ObjectLayout& layout, CollisionReport* report,
                        const SegmentOptions& options) {
  ++context.counters().segment_checks;
  detail::prepareResting(world, context, layout, std::span<const RobotState>(&start, 1));
  return robotSegment(world, context, start, q_end, report, options);
}

bool motionsInCollision(const CollisionWorld& world, CollisionContext& context, std::span<const RobotMotion> motions,
                        const ObjectLayout& layout, CollisionReport* report, const SegmentOptions& options) {
  ++context.counters().segment_checks;
  std::vector<RobotState> states;
  states.reserve(motions.size());
  for (const RobotMotion& m : motions) states.push_back(m.start);
  detail::prepareResting(world, context, layout, states);
  auto check_states = [&](double t) {
    ++context.counters().configuration_checks;
    for (std::size_t i = 0; i < motions.size(); ++i) states[i].q = interpolate(motions[i].start.q, motions[i].q_end, t);
    if (!detail::checkStates(world, context, states, options.scope, report)) return false;
    if (report != nullptr) report->segment_fraction = t;
    return true;
  };
  if (options.check_endpoints && (check_states(0.0) || check_states(1.0))) return true;

  // Robots whose swept boxes meet no other's cannot collide with each other along the motion.
  std::vector<Aabb> whole(motions.size());
  std::vector<Aabb> scratch_swept;
  Aabb held_swept;
  int n = 1;
  for (std::size_t i = 0; i < motions.size(); ++i) {
    const RobotMotion& m = motions[i];
    whole[i] = sweptBoxes(world, context, m.start.robot, m.start.q, m.q_end, m.start.held, scratch_swept, held_swept);
    n = std::max(n, segmentSteps(world, m.start.robot, m.start.q, m.q_end, m.start.held, options.resolution));
  }
  bool apart = options.scope == CheckScope::kObjectsOnly;
  if (!apart) {
    apart = true;
    for (std::size_t i = 0; i < motions.size() && apart; ++i) {
      for (std::size_t k = i + 1; k < motions.size() && apart; ++k) apart = !whole[i].intersects(whole[k]);
    }
  }
  if (apart) {
    SegmentOptions alone = options;
    alone.check_endpoints = false;
    for (const RobotMotion& m : motions) {
      if (robotSegment(world, context, m.start, m.q_end, report, alone)) return true;
    }
    return false;
  }
  return forEachInteriorStep(n, [&](int k) { return check_states(static_cast<double>(k) / n); });
}

}  // namespace dash
