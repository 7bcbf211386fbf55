#pragma once
// Forward and inverse kinematics for the models in robot_model.h. Free functions over an immutable
// model; X_WB is the robot's base (mounting) pose in the world.
#include <array>
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

// ---- Allocation-free variants for hot paths --------------------------------------------------

inline constexpr int kUrFrames = 7;  ///< DH frames 0 (base) .. 6 (flange)
inline constexpr int kUrMaxIkSolutions = 8;

/// UR arm: world poses of DH frames 0..6 (frame 0 = X_WB, frame 6 = flange).
void urFrames(const RobotModel& model, const Pose& X_WB, const JointVector& q,
              std::array<Pose, kUrFrames>& X_W);

/// UR arm: closed-form IK (the standard one for UR arms: shoulder pan x wrist 2 x elbow, up to 8
/// solutions). Writes the solutions into out[0..n) and returns n; no heap allocation.
///
/// Joints are wrapped into [-pi, pi]; a solution whose wrapped joint lies outside the model's limits
/// is shifted by 2 pi if that fits, else dropped. Branches that coincide (shoulder or elbow at the
/// boundary of the workspace, wrist singular) are returned once.
///
/// Wrist singularity rule: when |sin q5| < kUrWristSingularTolerance the flange z axis is parallel to
/// the shoulder axis z1 and only q4 + q6 (q5 ~ 0) or q4 - q6 (q5 ~ pi) is determined. Then q6 is
/// fixed to `q6_reference` (wrapped to [-pi, pi]; default 0) and q5 is snapped to exactly 0 or pi,
/// and q2, q3, q4 are solved for that q6. Pass the current q6 as the reference to keep the wrist
/// still. (q6 moves the wrist point p4 on a circle of radius d5. At the edge of the workspace, when
/// the reference - or, near the singularity, the ill-conditioned computed q6 - leaves p4 just out
/// of the elbow's reach, q6 is moved to the nearest value that brings p4 back to the boundary, or,
/// when the wrist is singular and none is near, to the circle point nearest to / farthest from the
/// shoulder; such a solution is kept only if FK reproduces the target to 1e-10.)
/// FK(solution) still matches the target to ~1e-12 there.
///
/// Targets out of reach return 0. Accuracy: every returned solution reproduces X_WT to ~1e-12 m /
/// rad; the recovered joint values lose accuracy like eps / distance-to-singularity near the
/// shoulder (wrist centre near the plane of z0 and z1), elbow (sin q3 ~ 0) and wrist singularities.
inline constexpr double kUrWristSingularTolerance = 1e-12;
int inverseKinematicsUr(const RobotModel& model, const Pose& X_WB, const Pose& X_WT,
                        std::array<JointVector, kUrMaxIkSolutions>& out, double q6_reference = 0.0);

/// Gantry: the unique IK solution. Returns 1 and writes q when X_WT has the tool-down orientation
/// (within kGantryOrientationTolerance rad) and the position is reachable within the limits (to
/// 1e-9, then clamped into them); returns 0 otherwise.
inline constexpr double kGantryOrientationTolerance = 1e-6;
int inverseKinematicsGantry(const RobotModel& model, const Pose& X_WB, const Pose& X_WT, JointVector& q);

/// Wraps an angle into [-pi, pi].
double wrapToPi(double angle);

}  // namespace dash
