#pragma once
// What a controller agent needs from the arm it runs next to: its joint state, and a goal's life
// cycle (load = check and prepare, start at a time, abort). SimDriver and UrDriver implement it.
// Every method is thread safe and returns promptly; execution happens on the driver's own threads.
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include "server/dispatch/arm_trajectory.h"
#include "server/dispatch/dispatch_protocol.h"
#include "server/dispatch/dispatch_types.h"

namespace dash::dispatch {

struct DriverState {
  bool valid = false;  ///< a measured state is available
  JointVector q;
  JointVector qd;
  std::int64_t stamp_us = 0;  ///< local steady time of the measurement (0: now)
};

struct DriverProgress {
  ArmStatus status = ArmStatus::kIdle;
  ResultCode result = ResultCode::kSuccessful;
  std::string message;
};

class ArmDriver {
 public:
  virtual ~ArmDriver() = default;
  virtual std::string kind() const = 0;   ///< "sim", "ur"
  virtual std::string model() const = 0;  ///< the robot model's name
  virtual std::vector<std::string> jointNames() const = 0;
  /// Whether a goal can be loaded now; otherwise `detail` says why (also set when ready).
  virtual bool ready(std::string& detail) const = 0;
  virtual DriverState state() const = 0;
  /// Checks a goal and prepares it (status kArmed). On a refusal returns its code (INVALID_GOAL,
  /// INVALID_JOINTS) with `message`, and the status becomes kFailed.
  virtual ResultCode load(const ArmTrajectory& trajectory, const GoalLimits& limits, std::string& message) = 0;
  /// Starts the loaded goal at `at` (now if already past).
  virtual void start(std::chrono::steady_clock::time_point at) = 0;
  /// Stops now. An armed goal is dropped; a running one is cancelled (kAborted, CANCELLED).
  virtual void abort(const std::string& reason) = 0;
  virtual DriverProgress progress() const = 0;
  /// "open", "closed" or "" (no gripper).
  virtual std::string gripperState() const { return ""; }
  /// Stops the driver's threads (the destructor also does).
  virtual void shutdown() {}
};

/// The checks every driver makes before loading a goal: structure (arm_trajectory.h), joint names
/// (INVALID_JOINTS), the first point at the measured state and every segment within velocity_max
/// (INVALID_GOAL). Returns kSuccessful or the refusal with `message`.
ResultCode checkGoal(const ArmTrajectory& trajectory, const std::vector<std::string>& joint_names,
                     const DriverState& state, const JointVector& velocity_max, const GoalLimits& limits,
                     std::string& message);

}  // namespace dash::dispatch
