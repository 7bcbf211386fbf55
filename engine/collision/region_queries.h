#pragma once
// Regions a robot must keep out of: the region p of a motion constraint C_M (paper, "Query
// (Motion-extended Hypergraph)": "motion constraints are applied to prevent traversal through regions
// defined by the boundaries of colliding objects and robots"). A region is a list of world boxes. The
// tests are conservative: a configuration or segment counts as entering when a box that contains a
// robot part (each body, the held object) meets a region box, so "free" proves the exact bodies stay out.
#include <span>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"

namespace dash {

/// Whether any body of the robot, or what it holds, at state.q may be inside one of `regions`.
bool robotEntersRegions(const CollisionWorld& world, CollisionContext& context, const RobotState& state,
                        std::span<const Aabb> regions);

/// Whether the robot may enter one of `regions` anywhere along start.q -> q_end (holding start.held):
/// the segment is cut as the collision checker cuts it (segmentSteps) and each part's swept boxes
/// (sweptPartBoxes) are tested.
bool segmentEntersRegions(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                          const JointVector& q_end, std::span<const Aabb> regions);

}  // namespace dash
