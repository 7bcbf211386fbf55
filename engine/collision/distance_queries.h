#pragma once
// Minimum distances (unsigned): 0 when the two shapes touch or overlap, between exact shapes (no
// contact tolerance, no clearance). Pairs whose bounding boxes are already farther apart
// than the best distance found are skipped.
#include <limits>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_report.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"
#include "engine/scene/object_layout.h"

namespace dash {

struct DistanceReport {
  CollisionElement a;  ///< a body or the held object of the robot asked about
  CollisionElement b;  ///< the closest obstacle, object or other robot's part
  double distance = std::numeric_limits<double>::infinity();
};

/// Signed distance between two shapes: their distance when apart, minus the penetration depth when
/// they overlap (FCL's contact depth), 0 when they touch. Counts one narrow-phase call.
double signedDistance(CollisionContext& context, const fcl::CollisionGeometry<double>& a, const Pose& X_WA,
                      const fcl::CollisionGeometry<double>& b, const Pose& X_WB);

/// Smallest distance from robot state.robot (bodies and held object) to any obstacle or resting object.
/// Infinity if there is nothing to measure against.
double robotDistance(const CollisionWorld& world, CollisionContext& context, const RobotState& state,
                     const ObjectLayout& layout, DistanceReport* report = nullptr);

/// Smallest distance between two robots' bodies and held objects.
double robotsDistance(const CollisionWorld& world, CollisionContext& context, const RobotState& a,
                      const RobotState& b, DistanceReport* report = nullptr);

}  // namespace dash
