#include "server/dispatch/arm_driver.h"

#include <cstdio>

namespace dash::dispatch {

ResultCode checkGoal(const ArmTrajectory& trajectory, const std::vector<std::string>& joint_names,
                     const DriverState& state, const JointVector& velocity_max, const GoalLimits& limits,
                     std::string& message) {
  if (trajectory.joint_names != joint_names) {
    std::string expected;
    for (const auto& n : joint_names) expected += (expected.empty() ? "" : ",") + n;
    message = "joint names do not match this arm's [" + expected + "]";
    return ResultCode::kInvalidJoints;
  }
  message = structuralProblem(trajectory, static_cast<int>(joint_names.size()));
  if (!message.empty()) return ResultCode::kInvalidGoal;
  if (!state.valid) {
    message = "the arm's joint state is not known";
    return ResultCode::kInvalidGoal;
  }
  const double off = maxAbsDifference(state.q, trajectory.points.front().positions);
  if (!(off <= limits.start_tolerance)) {
    char text[160];
    std::snprintf(text, sizeof text, "the first point is %.4f from the measured state (tolerance %.4f)", off,
                  limits.start_tolerance);
    message = text;
    return ResultCode::kInvalidGoal;
  }
  const PeakSpeed peak = peakSpeed(trajectory, velocity_max);
  if (peak.ratio > 1.0 + 1e-6) {
    char text[160];
    std::snprintf(text, sizeof text, "segment %d: joint %d would move at %.3f (limit %.3f)", peak.segment, peak.joint,
                  peak.speed, velocity_max[peak.joint]);
    message = text;
    return ResultCode::kInvalidGoal;
  }
  message.clear();
  return ResultCode::kSuccessful;
}

}  // namespace dash::dispatch
