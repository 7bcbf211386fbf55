#include "engine/motion/static_robot_validity.h"

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"

namespace dash {

StaticRobotValidity::StaticRobotValidity(const CollisionWorld& world, CollisionContext& context, int robot)
    : world_(&world), context_(&context), robot_(robot), none_(ObjectLayout::empty(world.scene())) {}

bool StaticRobotValidity::stateValid(const JointVector& q, const HeldObject& held) const {
  return !robotInCollision(*world_, *context_, RobotState{robot_, q, held}, none_, nullptr, CheckScope::kStaticOnly);
}

bool StaticRobotValidity::motionValid(const JointVector& a, const JointVector& b, const HeldObject& held) const {
  return !segmentInCollision(*world_, *context_, RobotState{robot_, a, held}, b, none_, nullptr,
                             SegmentOptions{.scope = CheckScope::kStaticOnly});
}

}  // namespace dash
