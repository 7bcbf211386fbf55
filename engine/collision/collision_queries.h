#pragma once
// Configuration queries. Each returns true when something collides and, if `report` is given, says
// which pair (the first one found). The rules follow formats.md:
//  - a robot's bodies: against its model's self_collision_pairs, obstacles, resting objects, other
//    robots' bodies and their held objects;
//  - a held object: against obstacles, resting objects, other robots and other held objects, and
//    against its own robot's bodies except the gripper bodies (RobotModel: is_gripper);
//  - an object held by a robot in the query never counts as resting, whatever the layout says;
//  - contact tolerance and clearance as collision_world.h says (contact only where contact is meant).
// Every call counts one configuration check in the context's counters.
#include <span>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_report.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"
#include "engine/scene/object_layout.h"

namespace dash {

/// One robot (with what it holds) against itself, obstacles and resting objects.
bool robotInCollision(const CollisionWorld& world, CollisionContext& context, const RobotState& state,
                      const ObjectLayout& layout, CollisionReport* report = nullptr,
                      CheckScope scope = CheckScope::kAll);

/// Several robots at once: each as in robotInCollision, plus robot-robot pairs (bodies and held objects).
/// kStaticOnly keeps the robot-robot pairs (they do not depend on the layout); kObjectsOnly checks only
/// robots and held objects against resting objects. Each robot may appear once.
bool robotsInCollision(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> states,
                       const ObjectLayout& layout, CollisionReport* report = nullptr,
                       CheckScope scope = CheckScope::kAll);

/// `states` as in robotsInCollision, and each of them against the robots standing still in `parked`
/// (bodies and held objects; not with kObjectsOnly). The parked robots are not checked against anything
/// else (obstacles, objects, each other): they were when they stopped there, and nothing here moves
/// them. A robot may appear once in both lists together.
bool robotsAmongParked(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> states,
                       std::span<const RobotState> parked, const ObjectLayout& layout,
                       CollisionReport* report = nullptr, CheckScope scope = CheckScope::kAll);

/// One object placed at X_WO (not held) against obstacles and the other resting objects of `layout`.
bool objectInCollision(const CollisionWorld& world, CollisionContext& context, int object, const Pose& X_WO,
                       const ObjectLayout& layout, CollisionReport* report = nullptr);

/// Every resting object of `layout` against obstacles and the other resting objects.
bool layoutInCollision(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                       CollisionReport* report = nullptr);

}  // namespace dash
