#pragma once
// Vocabulary shared by the dispatch server, the controller agents and their drivers: result codes
// (ROS 2 control_msgs/FollowJointTrajectory's, plus two of our own), arm states, timestamps.
#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "engine/robots/joint_vector.h"

namespace dash::dispatch {

/// Outcome of one arm's goal. 0 .. -5 are FollowJointTrajectory's error codes; the last two are not
/// part of that message: kCancelled (the goal was cancelled by an abort, an action's CANCELED status in
/// ROS 2) and kFault (the driver lost its robot or its server, or the robot stopped on its own).
enum class ResultCode : int {
  kSuccessful = 0,
  kInvalidGoal = -1,
  kInvalidJoints = -2,
  kOldHeaderTimestamp = -3,
  kPathToleranceViolated = -4,
  kGoalToleranceViolated = -5,
  kCancelled = -10,
  kFault = -11,
};

/// "SUCCESSFUL", "INVALID_GOAL", ..., "CANCELLED", "FAULT".
const char* resultCodeName(ResultCode code);
/// Inverse of resultCodeName; nullopt for an unknown name.
std::optional<ResultCode> resultCodeFromName(const std::string& name);
/// Inverse of static_cast<int>; nullopt for an unknown number.
std::optional<ResultCode> resultCodeFromInt(int code);

/// Where one arm stands with its current (or last) goal.
enum class ArmStatus {
  kIdle,       ///< no goal since the agent started
  kArmed,      ///< goal checked and loaded, waiting for the common start time
  kExecuting,  ///< moving (or waiting for the robot's answer)
  kSucceeded,  ///< reached the goal (result kSuccessful)
  kFailed,     ///< refused the goal or failed while executing (result says why)
  kAborted,    ///< stopped by an abort (result kCancelled or kFault)
};

const char* armStatusName(ArmStatus status);  ///< "idle", "armed", ...
std::optional<ArmStatus> armStatusFromName(const std::string& name);
/// Succeeded, failed or aborted: the goal is over.
inline bool isFinal(ArmStatus s) {
  return s == ArmStatus::kSucceeded || s == ArmStatus::kFailed || s == ArmStatus::kAborted;
}

/// Microseconds on the steady clock. The server stamps everything with its own steady clock; agents
/// translate to it with the offset they estimate (ClockSync in controller_agent.cpp).
inline std::int64_t steadyMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}
inline std::chrono::steady_clock::time_point steadyFromMicros(std::int64_t us) {
  return std::chrono::steady_clock::time_point(std::chrono::microseconds(us));
}

/// One measured joint state, stamped in server time (microseconds).
struct JointSample {
  std::int64_t t_us = 0;
  JointVector q;
  JointVector qd;  ///< may be empty when the driver does not measure velocities
};

/// Largest |a_i - b_i| (infinity if the sizes differ).
double maxAbsDifference(const JointVector& a, const JointVector& b);

}  // namespace dash::dispatch
