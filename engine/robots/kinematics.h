#pragma once
// Forward and inverse kinematics for the models in robot_model.h. Free functions over an immutable
// model; X_WB is the robot's base (mounting) pose in the world.
#include <span>
#include <vector>

#include "engine/robots/robot_model.h"

namespace dash {

struct FkResult {
  Pose X_WF = Pose::Identity();  ///< flange (UR) or carriage-less tool mount (gantry: same as TCP)
  Pose X_WT = Pose::Identity();  ///< TCP
};

FkResult forwardKinematics(const RobotModel& model, const Pose& X_WB, const JointVector& q);

/// World pose of the frame of every collision body, in model.bodies order (out.size() == bodies).
/// For a UR arm that is the body's DH frame; for a gantry it is the moved box centre.
void bodyFrames(const RobotModel& model, const Pose& X_WB, const JointVector& q, std::span<Pose> out);

/// All IK solutions that reach X_WT (the TCP pose), within joint limits, each joint wrapped
/// into the planning range [-pi, pi] where the limits allow. UR: up to 8; gantry: 0 or 1.
std::vector<JointVector> inverseKinematics(const RobotModel& model, const Pose& X_WB, const Pose& X_WT);

}  // namespace dash
