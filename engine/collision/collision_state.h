#pragma once
// What a collision query is asked about: the configuration of each robot involved and what it holds.
// Resting objects come from an ObjectLayout (engine/scene/object_layout.h). Plain aggregates.
#include "engine/geometry/pose.h"
#include "engine/robots/joint_vector.h"
#include "engine/scene/object_layout.h"

namespace dash {

/// An object rigidly attached to a robot's TCP: its world pose is X_WT * X_TO (formats.md, grasp).
struct HeldObject {
  int object = -1;                ///< index into Scene::objects; -1 = empty hand
  Pose X_TO = Pose::Identity();   ///< object in the TCP frame
  /// Carried between the approach lines of its pick and its place (roadmap transit), far from what it
  /// rests on: its lowest face keeps the clearance too. Otherwise (on an approach line, at a grasp or
  /// release) that face may touch what the object rests on (collision_world.h).
  bool in_transit = false;
  bool holding() const { return object >= 0; }
};

/// `held` as carried in transit (see HeldObject::in_transit); an empty hand stays empty.
inline HeldObject inTransit(HeldObject held) {
  held.in_transit = held.holding();
  return held;
}

/// One robot's part of a query.
struct RobotState {
  int robot = -1;  ///< index into Scene::robots
  JointVector q;
  HeldObject held;
};

/// Which pairs a query looks at. Planners cache the static part on roadmaps (it never changes during
/// a plan) and check the object part against the layout of the moment (planner-notes.md).
enum class CheckScope {
  kAll,          ///< static + objects
  kStaticOnly,   ///< self pairs, obstacles, held object vs obstacles and the robot's own bodies
  kObjectsOnly,  ///< robot bodies and held object vs resting objects
  kRobotsOnly,   ///< robot against robot only: each pair's bodies and held objects (several robots)
};

}  // namespace dash
