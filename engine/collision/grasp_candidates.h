#pragma once
// Grasp candidates for a box: where the TCP goes and how the object then sits in the TCP frame
// (the X_TO of a plan's grasp event). Shared by the scene checker, the planners and the generators.
//
//  - UR arms (parallel gripper closing along the TCP x axis, approaching along TCP z): the TCP at the
//    box centre, approach axis along the inward normal of each face (top, bottom and the four sides,
//    named in the object frame: top = +z), two rotations about it (fingers closing across either
//    in-face axis). A candidate is kept only if the box fits between the fingers (the opening is read
//    from the model's gripper boxes).
//  - Gantries: one top grasp with the tool pointing down (the only orientation a gantry has), the TCP
//    at the centre of the box face that points up, where the tool holds it (gantry3.json). None if no
//    face points up within kGraspUprightTolerance.
// Candidates say nothing about reachability or collisions: run inverseKinematics and the collision
// queries on X_WT.
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/geometry/shapes.h"
#include "engine/robots/robot_model.h"

namespace dash {

inline constexpr double kGraspUprightTolerance = 0.05;  ///< rad, a gantry's top face against world +z

struct GraspCandidate {
  enum class Face { kTop, kBottom, kPlusX, kMinusX, kPlusY, kMinusY };  ///< in the object frame
  Face face = Face::kTop;
  int rotation = 0;              ///< 0 or 1: quarter turns of the gripper about the approach axis
  Pose X_TO = Pose::Identity();  ///< object in the TCP frame while held
  Pose X_WT = Pose::Identity();  ///< TCP in the world for the object pose asked about
};

const char* faceName(GraspCandidate::Face face);

/// Candidates for grasping `box` resting at X_WO with a robot of `model` mounted at X_WB.
std::vector<GraspCandidate> graspCandidates(const RobotModel& model, const Pose& X_WB, const BoxShape& box,
                                            const Pose& X_WO);

/// Distance between the inner faces of the gripper's fingers (along TCP x), or infinity if the model
/// has no finger boxes.
double gripperOpening(const RobotModel& model);

}  // namespace dash
