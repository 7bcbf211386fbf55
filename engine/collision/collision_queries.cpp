#include "engine/collision/collision_queries.h"

#include <fcl/narrowphase/collision.h>

#include "engine/collision/collision_internal.h"
#include "engine/collision/cover_check.h"
#include "engine/core/check.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace detail {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// The resting object (among `objects`) whose box is nearest the TCP at p_WT, if within kGraspReach of
/// it: the one a gripper there grasps or has just let go. -1 if none.
int graspedObject(const CollisionWorld& world, const std::vector<Pose>& object_pose, std::span<const int> objects,
                  const Vec3& p_WT) {
  int nearest = -1;
  double best = kGraspReach;
  for (const int j : objects) {
    const Vec3 p_OT = object_pose[at(j)].inverse() * p_WT;
    const double d = (p_OT.cwiseAbs() - world.object(j).half_extents).cwiseMax(0.0).norm();
    if (d <= best) {
      best = d;
      nearest = j;
    }
  }
  return nearest;
}

void setReport(CollisionReport* report, const CollisionElement& a, const CollisionElement& b) {
  if (report != nullptr) *report = CollisionReport{.a = a, .b = b};
}

}  // namespace

bool shapesCollide(CollisionContext& context, const fcl::CollisionGeometry<double>& a, const Pose& X_WA,
                   const fcl::CollisionGeometry<double>& b, const Pose& X_WB) {
  ++context.counters().narrowphase_calls;
  const fcl::CollisionRequestd request;  // one contact, no contact details: a yes/no answer
  fcl::CollisionResultd result;
  return fcl::collide(&a, X_WA, &b, X_WB, request, result) > 0;
}

void poseRobot(const CollisionWorld& world, CollisionContext& context, int r, const JointVector& q,
               const HeldObject& held) {
  const RobotGeometry& rg = world.robot(r);
  DASH_DEMAND_MSG(q.size() == rg.model->dof(), "configuration size does not match the robot");
  // A NaN would make every bounding-box test fail, i.e. report "free".
  DASH_DEMAND_MSG(q.allFinite(), "configuration is not finite");
  auto& posed = context.scratch().robots[at(r)];
  bodyFrames(*rg.model, rg.robot->X_WB, q, posed.frames);
  // Boxes hold the grown shapes (the largest growth is the whole clearance).
  const double margin = world.clearance();
  posed.aabb.setEmpty();
  for (std::size_t b = 0; b < rg.bodies.size(); ++b) {
    const BodyGeometry& g = rg.bodies[b];
    const Pose& X_WF = posed.frames[b];
    Aabb& box = posed.body_aabb[b];
    if (g.is_capsule) {
      const Vec3 p_a = X_WF * g.a;
      const Vec3 p_b = X_WF * g.b;
      box = Aabb(p_a.cwiseMin(p_b).array() - g.radius - margin, p_a.cwiseMax(p_b).array() + g.radius + margin);
    } else {
      const Vec3 c = X_WF * g.center;
      const Vec3 extent = X_WF.linear().cwiseAbs() * g.half_extents + Vec3::Constant(margin);
      box = Aabb(c - extent, c + extent);
    }
    posed.aabb.extend(box);
  }
  posed.held_object = held.object;
  posed.held_in_transit = held.in_transit;
  if (held.holding()) {
    DASH_DEMAND(held.object < world.objectCount());
    posed.X_WO_held = forwardKinematics(*rg.model, rg.robot->X_WB, q).X_WT * held.X_TO;
    posed.held_aabb = boxAabb(posed.X_WO_held, world.object(held.object).half_extents + Vec3::Constant(margin));
  }
}

void prepareResting(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                    std::span<const RobotState> states) {
  DASH_DEMAND_MSG(layout.size() == world.objectCount(), "object layout does not match the scene");
  auto& s = context.scratch();
  s.resting.assign(layout.present.begin(), layout.present.end());
  for (const RobotState& state : states) {
    if (state.held.holding()) s.resting[at(state.held.object)] = 0;
  }
  s.resting_list.clear();
  for (int j = 0; j < layout.size(); ++j) {
    if (s.resting[at(j)] == 0) continue;
    s.resting_list.push_back(j);
    s.object_pose[at(j)] = layout.X_WO[at(j)];
    s.object_aabb[at(j)] = boxAabb(layout.X_WO[at(j)], world.object(j).half_extents);
  }
}

CandidateView fullCandidates(const CollisionWorld& world, CollisionContext& context, int r, CheckScope scope) {
  CandidateView view;
  const RobotGeometry& rg = world.robot(r);
  if (scope != CheckScope::kObjectsOnly) {
    view.obstacles = rg.nearby_obstacles;
    view.held_obstacles = world.allObstacles();
    view.self_pairs = rg.model->self_collision_pairs;
    view.held_vs_bodies = rg.non_gripper_bodies;
  }
  if (scope != CheckScope::kStaticOnly) {
    view.objects = context.scratch().resting_list;
  }
  return view;
}

namespace {

using PosedRobot = CollisionContext::PosedRobot;

/// Posed robot r's bodies against the candidate obstacles, each behind the whole-robot box, then each
/// body's box.
bool bodiesHitObstacles(const CollisionWorld& world, CollisionContext& context, int r, const PosedRobot& posed,
                        const CandidateView& candidates, CollisionReport* report) {
  const RobotGeometry& rg = world.robot(r);
  const int bodies = static_cast<int>(rg.bodies.size());
  for (const int i : candidates.obstacles) {
    const ObstacleGeometry& obstacle = world.obstacles()[at(i)];
    if (!posed.aabb.intersects(obstacle.aabb)) continue;
    for (int b = 0; b < bodies; ++b) {
      if (!posed.body_aabb[at(b)].intersects(obstacle.aabb)) continue;
      if (bodyBoxApart(world, context, r, b, obstacle.X_WO, obstacle.half_extents)) continue;
      if (shapesCollide(context, *rg.bodies[at(b)].shape_vs_static, bodyPose(world, posed, r, b), *obstacle.shape,
                        obstacle.X_WO)) {
        setReport(report, CollisionElement::robotBody(r, b), CollisionElement::obstacle(i));
        return true;
      }
    }
  }
  return false;
}

/// Posed robot r's candidate self-collision pairs.
bool bodiesHitEachOther(const CollisionWorld& world, CollisionContext& context, int r, const PosedRobot& posed,
                        const CandidateView& candidates, CollisionReport* report) {
  const RobotGeometry& rg = world.robot(r);
  for (const auto& [b1, b2] : candidates.self_pairs) {
    if (!posed.body_aabb[at(b1)].intersects(posed.body_aabb[at(b2)])) continue;
    if (bodiesApart(world, context, r, b1, r, b2)) continue;
    if (shapesCollide(context, *rg.bodies[at(b1)].shape_vs_robot, bodyPose(world, posed, r, b1),
                      *rg.bodies[at(b2)].shape_vs_robot, bodyPose(world, posed, r, b2))) {
      setReport(report, CollisionElement::robotBody(r, b1), CollisionElement::robotBody(r, b2));
      return true;
    }
  }
  return false;
}

/// Posed robot r's bodies against the candidate resting objects. A gripper may touch the resting object
/// it grasps or has just let go (the one nearest its TCP); every other resting object keeps the
/// clearance from it.
bool bodiesHitObjects(const CollisionWorld& world, CollisionContext& context, int r, const PosedRobot& posed,
                      const CandidateView& candidates, CollisionReport* report) {
  const RobotGeometry& rg = world.robot(r);
  auto& s = context.scratch();
  const int bodies = static_cast<int>(rg.bodies.size());
  constexpr int kUnknown = -2;
  int grasped = kUnknown;  // the resting object the gripper may touch, found when first needed
  for (const int j : candidates.objects) {
    const Aabb& object_box = s.object_aabb[at(j)];
    if (!posed.aabb.intersects(object_box)) continue;
    for (int b = 0; b < bodies; ++b) {
      if (!posed.body_aabb[at(b)].intersects(object_box)) continue;
      if (bodyBoxApart(world, context, r, b, s.object_pose[at(j)], world.object(j).half_extents)) continue;
      const BodyGeometry& body = rg.bodies[at(b)];
      const ObjectGeometry& object = world.object(j);
      // A hand that holds an object grasps no resting one: its gripper keeps the clearance from all of
      // them (placing next to a neighbour, the TCP may be nearer the neighbour than anything else).
      if (body.is_gripper && grasped == kUnknown) {
        grasped = posed.held_object >= 0
                      ? -1
                      : graspedObject(world, s.object_pose, s.resting_list,
                                      posed.frames[at(b)] * body.X_FT.translation());
      }
      const bool contact = body.is_gripper && j == grasped;
      if (shapesCollide(context, contact ? *body.shape : *body.shape_vs_static, bodyPose(world, posed, r, b),
                        contact ? *object.contact_shape : *object.shape, s.object_pose[at(j)])) {
        setReport(report, CollisionElement::robotBody(r, b), CollisionElement::object(j));
        return true;
      }
    }
  }
  return false;
}

/// What posed robot r holds against the candidate obstacles, r's own bodies and the resting objects.
bool heldObjectHits(const CollisionWorld& world, CollisionContext& context, int r, const PosedRobot& posed,
                    const CandidateView& candidates, CollisionReport* report) {
  const RobotGeometry& rg = world.robot(r);
  auto& s = context.scratch();
  const int held = posed.held_object;
  const auto& held_shape = *world.object(held).held_vs_robot;
  const PosedShape held_static = posed.held_in_transit
                                     ? PosedShape{world.object(held).held_in_transit.get(), posed.X_WO_held}
                                     : heldStaticShape(world, held, posed.X_WO_held);
  const CollisionElement held_element = CollisionElement::heldObject(r, held);
  for (const int i : candidates.held_obstacles) {
    const ObstacleGeometry& obstacle = world.obstacles()[at(i)];
    if (!posed.held_aabb.intersects(obstacle.aabb)) continue;
    if (heldBoxApart(world, context, r, obstacle.X_WO, obstacle.half_extents)) continue;
    if (shapesCollide(context, *held_static.shape, held_static.X_WS, *obstacle.shape, obstacle.X_WO)) {
      setReport(report, held_element, CollisionElement::obstacle(i));
      return true;
    }
  }
  for (const int b : candidates.held_vs_bodies) {
    if (!posed.held_aabb.intersects(posed.body_aabb[at(b)])) continue;
    if (heldBodyApart(world, context, r, r, b)) continue;
    if (shapesCollide(context, held_shape, posed.X_WO_held, *rg.bodies[at(b)].shape_vs_robot,
                      bodyPose(world, posed, r, b))) {
      setReport(report, held_element, CollisionElement::robotBody(r, b));
      return true;
    }
  }
  for (const int j : candidates.objects) {
    if (!posed.held_aabb.intersects(s.object_aabb[at(j)])) continue;
    if (heldBoxApart(world, context, r, s.object_pose[at(j)], world.object(j).half_extents)) continue;
    if (shapesCollide(context, *held_static.shape, held_static.X_WS, *world.object(j).shape, s.object_pose[at(j)])) {
      setReport(report, held_element, CollisionElement::object(j));
      return true;
    }
  }
  return false;
}

}  // namespace

// Obstacles first (the likeliest hits), then self pairs, resting objects, other robots, and what the
// robot holds.
bool checkPosedRobot(const CollisionWorld& world, CollisionContext& context, int r, const CandidateView& candidates,
                     CollisionReport* report) {
  const PosedRobot& posed = context.scratch().robots[at(r)];
  if (bodiesHitObstacles(world, context, r, posed, candidates, report)) return true;
  if (bodiesHitEachOther(world, context, r, posed, candidates, report)) return true;
  if (bodiesHitObjects(world, context, r, posed, candidates, report)) return true;
  for (const int p : candidates.robots) {
    if (checkPosedRobotPair(world, context, r, p, report)) return true;
  }
  return posed.held_object >= 0 && heldObjectHits(world, context, r, posed, candidates, report);
}

namespace {

/// Held object of posed robot `holder` against the bodies of posed robot r. The other robot's gripper
/// bodies do not count when it holds the same object (a handover).
bool heldAgainstRobot(const CollisionWorld& world, CollisionContext& context, int holder, int r,
                      CollisionReport* report) {
  const auto& s = context.scratch();
  const auto& h = s.robots[at(holder)];
  const auto& posed = s.robots[at(r)];
  if (h.held_object < 0 || !h.held_aabb.intersects(posed.aabb)) return false;
  const RobotGeometry& rg = world.robot(r);
  const bool same_object = posed.held_object == h.held_object;
  for (int b = 0; b < static_cast<int>(rg.bodies.size()); ++b) {
    if (same_object && rg.bodies[at(b)].is_gripper) continue;
    if (!h.held_aabb.intersects(posed.body_aabb[at(b)])) continue;
    if (heldBodyApart(world, context, holder, r, b)) continue;
    if (shapesCollide(context, *world.object(h.held_object).held_vs_robot, h.X_WO_held,
                      *rg.bodies[at(b)].shape_vs_robot, bodyPose(world, posed, r, b))) {
      setReport(report, CollisionElement::heldObject(holder, h.held_object), CollisionElement::robotBody(r, b));
      return true;
    }
  }
  return false;
}

}  // namespace

bool checkPosedRobotPair(const CollisionWorld& world, CollisionContext& context, int r1, int r2,
                         CollisionReport* report) {
  const auto& s = context.scratch();
  const auto& p1 = s.robots[at(r1)];
  const auto& p2 = s.robots[at(r2)];
  const RobotGeometry& g1 = world.robot(r1);
  const RobotGeometry& g2 = world.robot(r2);
  if (p1.aabb.intersects(p2.aabb)) {
    for (int b1 = 0; b1 < static_cast<int>(g1.bodies.size()); ++b1) {
      if (!p1.body_aabb[at(b1)].intersects(p2.aabb)) continue;
      for (int b2 = 0; b2 < static_cast<int>(g2.bodies.size()); ++b2) {
        if (!p1.body_aabb[at(b1)].intersects(p2.body_aabb[at(b2)])) continue;
        if (bodiesApart(world, context, r1, b1, r2, b2)) continue;
        if (shapesCollide(context, *g1.bodies[at(b1)].shape_vs_robot, bodyPose(world, p1, r1, b1),
                          *g2.bodies[at(b2)].shape_vs_robot, bodyPose(world, p2, r2, b2))) {
          setReport(report, CollisionElement::robotBody(r1, b1), CollisionElement::robotBody(r2, b2));
          return true;
        }
      }
    }
  }
  if (heldAgainstRobot(world, context, r1, r2, report)) return true;
  if (heldAgainstRobot(world, context, r2, r1, report)) return true;
  if (p1.held_object >= 0 && p2.held_object >= 0 && p1.held_object != p2.held_object &&
      p1.held_aabb.intersects(p2.held_aabb) && !heldObjectsApart(world, context, r1, r2) &&
      shapesCollide(context, *world.object(p1.held_object).held_vs_robot, p1.X_WO_held,
                    *world.object(p2.held_object).held_vs_robot, p2.X_WO_held)) {
    setReport(report, CollisionElement::heldObject(r1, p1.held_object),
              CollisionElement::heldObject(r2, p2.held_object));
    return true;
  }
  return false;
}

void poseParked(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> parked,
                std::vector<int>& robots) {
  robots.clear();
  for (const RobotState& p : parked) {
    DASH_DEMAND(p.robot >= 0 && p.robot < world.robotCount());
    poseRobot(world, context, p.robot, p.q, p.held);
    robots.push_back(p.robot);
  }
}

bool checkStates(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> states,
                 CheckScope scope, CollisionReport* report, std::span<const int> parked) {
  for (std::size_t i = 0; i < states.size(); ++i) {
    const RobotState& state = states[i];
    DASH_DEMAND(state.robot >= 0 && state.robot < world.robotCount());
    for (std::size_t k = 0; k < i; ++k) DASH_DEMAND_MSG(states[k].robot != state.robot, "a robot appears twice");
    poseRobot(world, context, state.robot, state.q, state.held);
  }
  for (const RobotState& state : states) {
    if (scope == CheckScope::kRobotsOnly) break;
    if (checkPosedRobot(world, context, state.robot, fullCandidates(world, context, state.robot, scope), report)) {
      return true;
    }
  }
  if (scope == CheckScope::kObjectsOnly) return false;
  for (std::size_t i = 0; i < states.size(); ++i) {
    for (std::size_t k = i + 1; k < states.size(); ++k) {
      if (checkPosedRobotPair(world, context, states[i].robot, states[k].robot, report)) return true;
    }
    for (const int p : parked) {
      if (checkPosedRobotPair(world, context, states[i].robot, p, report)) return true;
    }
  }
  return false;
}

}  // namespace detail

bool robotInCollision(const CollisionWorld& world, CollisionContext& context, const RobotState& state,
                      const ObjectLayout& layout, CollisionReport* report, CheckScope scope) {
  ++context.counters().configuration_checks;
  const std::span<const RobotState> states(&state, 1);
  detail::prepareResting(world, context, layout, states);
  return detail::checkStates(world, context, states, scope, report);
}

bool robotsInCollision(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> states,
                       const ObjectLayout& layout, CollisionReport* report, CheckScope scope) {
  ++context.counters().configuration_checks;
  detail::prepareResting(world, context, layout, states);
  return detail::checkStates(world, context, states, scope, report);
}

bool robotsAmongParked(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> states,
                       std::span<const RobotState> parked, const ObjectLayout& layout, CollisionReport* report,
                       CheckScope scope) {
  if (parked.empty()) return robotsInCollision(world, context, states, layout, report, scope);
  ++context.counters().configuration_checks;
  std::vector<RobotState> all(states.begin(), states.end());
  all.insert(all.end(), parked.begin(), parked.end());
  for (std::size_t i = 0; i < all.size(); ++i)
    for (std::size_t k = 0; k < i; ++k) DASH_DEMAND_MSG(all[k].robot != all[i].robot, "a robot appears twice");
  detail::prepareResting(world, context, layout, all);
  // Every parked robot: the pair check's boxes clear the far ones at once (checkStates poses `states`).
  std::vector<int> robots;
  detail::poseParked(world, context, parked, robots);
  return detail::checkStates(world, context, states, scope, report, robots);
}

bool objectInCollision(const CollisionWorld& world, CollisionContext& context, int object, const Pose& X_WO,
                       const ObjectLayout& layout, CollisionReport* report) {
  DASH_DEMAND(object >= 0 && object < world.objectCount());
  DASH_DEMAND_MSG(layout.size() == world.objectCount(), "object layout does not match the scene");
  ++context.counters().configuration_checks;
  const ObjectGeometry& g = world.object(object);
  const Aabb box = boxAabb(X_WO, g.contact_half_extents);
  for (std::size_t i = 0; i < world.obstacles().size(); ++i) {
    const ObstacleGeometry& obstacle = world.obstacles()[i];
    if (!box.intersects(obstacle.aabb)) continue;
    if (detail::shapesCollide(context, *g.contact_shape, X_WO, *obstacle.shape, obstacle.X_WO)) {
      if (report != nullptr) {
        *report = {.a = CollisionElement::object(object), .b = CollisionElement::obstacle(static_cast<int>(i))};
      }
      return true;
    }
  }
  for (int k = 0; k < layout.size(); ++k) {
    if (k == object || !layout.isPresent(k)) continue;
    const Pose& X_WK = layout.X_WO[static_cast<std::size_t>(k)];
    if (!box.intersects(boxAabb(X_WK, world.object(k).contact_half_extents))) continue;
    if (detail::shapesCollide(context, *g.contact_shape, X_WO, *world.object(k).contact_shape, X_WK)) {
      if (report != nullptr) *report = {.a = CollisionElement::object(object), .b = CollisionElement::object(k)};
      return true;
    }
  }
  return false;
}

bool layoutInCollision(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                       CollisionReport* report) {
  // Each object against obstacles and the objects after it (each pair once).
  ObjectLayout later = layout;
  for (int j = 0; j < layout.size(); ++j) {
    later.remove(j);
    if (!layout.isPresent(j)) continue;
    if (objectInCollision(world, context, j, layout.X_WO[static_cast<std::size_t>(j)], later, report)) return true;
  }
  return false;
}

}  // namespace dash
