#pragma once
// Where a robot that is in the way waits while others do a step (ARC's subproblem moves it there):
// its home if that is clear, else a few fixed parking configurations of the arm (turned away from the
// work, or standing upright above its base). Gantries and arms whose home is clear just go home.
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_state.h"

namespace dash {

/// The first of home and the arm's parking configurations at which `robot` (holding `held`) is clear of
/// itself, the obstacles, the resting objects of `layout` and every robot state in `keep_clear_of`;
/// home when none is.
JointVector parkingConfiguration(const CollisionWorld& world, CollisionContext& context, int robot,
                                 const HeldObject& held, const std::vector<RobotState>& keep_clear_of,
                                 const ObjectLayout& layout);

}  // namespace dash
