#pragma once
// Building blocks shared by the query files of engine/collision. Not for use outside this folder.
#include <span>
#include <utility>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_report.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"
#include "engine/scene/object_layout.h"

namespace dash::detail {

/// The pairs one posed robot is checked against.
struct CandidateView {
  std::span<const int> obstacles;       ///< against the robot's bodies
  std::span<const int> held_obstacles;  ///< against its held object
  std::span<const int> objects;         ///< resting objects, against bodies and held object
  std::span<const std::pair<int, int>> self_pairs;
  std::span<const int> held_vs_bodies;  ///< own bodies against the held object
  std::span<const int> robots;          ///< robots standing still, already posed: bodies and held objects
};

/// A posed robot's box: its bodies and what it holds.
inline Aabb postureBox(const CollisionContext::PosedRobot& posed) {
  return posed.held_object >= 0 ? posed.aabb.merged(posed.held_aabb) : posed.aabb;
}

/// Poses the robots standing still of a query (once: they do not move); their indices in `robots`.
void poseParked(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> parked,
                std::vector<int>& robots);

/// Poses robot r's bodies (and held object) in context.scratch().robots[r].
void poseRobot(const CollisionWorld& world, CollisionContext& context, int r, const JointVector& q,
               const HeldObject& held);

/// Resting set of a query: present in the layout and not held by any of `states`.
void prepareResting(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                    std::span<const RobotState> states);

/// Every pair of `scope` for robot r (after prepareResting).
CandidateView fullCandidates(const CollisionWorld& world, CollisionContext& context, int r, CheckScope scope);

/// Robot r, already posed, against its candidates.
bool checkPosedRobot(const CollisionWorld& world, CollisionContext& context, int r, const CandidateView& candidates,
                     CollisionReport* report);

/// Two posed robots against each other: bodies, and held objects against bodies and each other.
bool checkPosedRobotPair(const CollisionWorld& world, CollisionContext& context, int r1, int r2,
                         CollisionReport* report);

/// Poses and checks several robots (each once) with a prepared resting set; each of them also against
/// the posed robots standing still in `parked` (unless kObjectsOnly).
bool checkStates(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> states,
                 CheckScope scope, CollisionReport* report, std::span<const int> parked = {});

/// World pose of body b of a posed robot, for FCL.
inline Pose bodyPose(const CollisionWorld& world, const CollisionContext::PosedRobot& posed, int r, int b) {
  return posed.frames[static_cast<std::size_t>(b)] * world.robot(r).bodies[static_cast<std::size_t>(b)].X_FG;
}

/// One FCL collide call (counted).
bool shapesCollide(CollisionContext& context, const fcl::CollisionGeometry<double>& a, const Pose& X_WA,
                   const fcl::CollisionGeometry<double>& b, const Pose& X_WB);

}  // namespace dash::detail
