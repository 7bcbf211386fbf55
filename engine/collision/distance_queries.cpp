#include "engine/collision/distance_queries.h"

#include <algorithm>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/distance.h>
#include <vector>

#include "engine/collision/collision_internal.h"

namespace dash {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

struct Part {
  CollisionElement element;
  const fcl::CollisionGeometry<double>* shape = nullptr;
  Pose X_WP = Pose::Identity();
  Aabb box;
  bool gripper = false;
};

/// The bodies and held object of a posed robot.
void robotParts(const CollisionWorld& world, const CollisionContext::PosedRobot& posed, int r, std::vector<Part>& out) {
  const RobotGeometry& rg = world.robot(r);
  for (int b = 0; b < static_cast<int>(rg.bodies.size()); ++b) {
    out.push_back({CollisionElement::robotBody(r, b), rg.bodies[at(b)].shape.get(), detail::bodyPose(world, posed, r, b),
                   posed.body_aabb[at(b)], rg.bodies[at(b)].is_gripper});
  }
  if (posed.held_object >= 0) {
    out.push_back({CollisionElement::heldObject(r, posed.held_object), world.object(posed.held_object).shape.get(),
                   posed.X_WO_held, posed.held_aabb, false});
  }
}

double shapeDistance(CollisionContext& context, const Part& a, const Part& b) {
  ++context.counters().narrowphase_calls;
  const fcl::DistanceRequestd request;
  fcl::DistanceResultd result;
  const double d = fcl::distance(a.shape, a.X_WP, b.shape, b.X_WP, request, result);
  return std::max(d, 0.0);  // FCL answers -1 for overlapping shapes without signed distance
}

/// Closest pair between two part lists, skipping pairs `skip` says are exempt.
template <class Skip>
double closest(CollisionContext& context, const std::vector<Part>& as, const std::vector<Part>& bs, Skip skip,
               DistanceReport* report) {
  double best = std::numeric_limits<double>::infinity();
  for (const Part& a : as) {
    for (const Part& b : bs) {
      if (skip(a, b) || a.box.exteriorDistance(b.box) >= best) continue;
      const double d = shapeDistance(context, a, b);
      if (d < best) {
        best = d;
        if (report != nullptr) *report = {.a = a.element, .b = b.element, .distance = d};
      }
      if (best <= 0.0) return 0.0;
    }
  }
  return best;
}

}  // namespace

double signedDistance(CollisionContext& context, const fcl::CollisionGeometry<double>& a, const Pose& X_WA,
                      const fcl::CollisionGeometry<double>& b, const Pose& X_WB) {
  ++context.counters().narrowphase_calls;
  // FCL's own GJK: measured several times faster here than libccd's for capsules and boxes.
  fcl::DistanceRequestd request;
  request.gjk_solver_type = fcl::GST_INDEP;
  fcl::DistanceResultd result;
  const double d = fcl::distance(&a, X_WA, &b, X_WB, request, result);
  if (d > 0.0) return d;
  // Overlapping (FCL answers -1) or touching: the depth of the deepest contact.
  fcl::CollisionRequestd contact_request(1, true);
  fcl::CollisionResultd contact_result;
  if (fcl::collide(&a, X_WA, &b, X_WB, contact_request, contact_result) == 0) return 0.0;
  double depth = 0.0;
  for (std::size_t i = 0; i < contact_result.numContacts(); ++i) {
    depth = std::max(depth, contact_result.getContact(i).penetration_depth);
  }
  return -depth;
}

double robotDistance(const CollisionWorld& world, CollisionContext& context, const RobotState& state,
                     const ObjectLayout& layout, DistanceReport* report) {
  ++context.counters().distance_queries;
  const std::span<const RobotState> states(&state, 1);
  detail::prepareResting(world, context, layout, states);
  detail::poseRobot(world, context, state.robot, state.q, state.held);
  std::vector<Part> parts;
  robotParts(world, context.scratch().robots[at(state.robot)], state.robot, parts);
  std::vector<Part> others;
  for (int i = 0; i < static_cast<int>(world.obstacles().size()); ++i) {
    const ObstacleGeometry& o = world.obstacles()[at(i)];
    others.push_back({CollisionElement::obstacle(i), o.shape.get(), o.X_WO, o.aabb, false});
  }
  const auto& s = context.scratch();
  for (const int j : s.resting_list) {
    others.push_back({CollisionElement::object(j), world.object(j).shape.get(), s.object_pose[at(j)], s.object_aabb[at(j)], false});
  }
  if (report != nullptr) *report = {};
  return closest(context, parts, others, [](const Part&, const Part&) { return false; }, report);
}

double robotsDistance(const CollisionWorld& world, CollisionContext& context, const RobotState& a,
                      const RobotState& b, DistanceReport* report) {
  ++context.counters().distance_queries;
  detail::poseRobot(world, context, a.robot, a.q, a.held);
  detail::poseRobot(world, context, b.robot, b.q, b.held);
  std::vector<Part> parts_a;
  std::vector<Part> parts_b;
  robotParts(world, context.scratch().robots[at(a.robot)], a.robot, parts_a);
  robotParts(world, context.scratch().robots[at(b.robot)], b.robot, parts_b);
  const int shared = a.held.holding() && a.held.object == b.held.object ? a.held.object : -1;
  // In a handover both grippers hold the same object: it does not count against either gripper.
  auto exempt = [shared](const Part& pa, const Part& pb) {
    if (shared < 0) return false;
    const bool a_held = pa.element.kind == CollisionElement::Kind::kHeldObject;
    const bool b_held = pb.element.kind == CollisionElement::Kind::kHeldObject;
    return (a_held && b_held) || (a_held && pb.gripper) || (b_held && pa.gripper);
  };
  if (report != nullptr) *report = {};
  return closest(context, parts_a, parts_b, exempt, report);
}

}  // namespace dash
