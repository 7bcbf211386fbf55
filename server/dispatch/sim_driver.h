#pragma once
// A simulated arm for `dashbench controller --driver sim`: it follows its goal in real time along the
// same curve the server expects (ArmTrajectory::positionAt), never faster than the model's
// velocity_max, and reports the state it actually reached. It can misbehave the way real arms do
// (issue 39): run slower than planned (speed < 1, a lowered speed slider), pause at random (a PC
// stall, a protective slowdown), and take time to close or open its gripper (a Hand-E takes about a
// second, more or less depending on the object); a goal ends only once its gripper has finished.
// Faults for tests: a silent stop mid-trajectory, a refused goal. (A dropped connection is the
// agent's --sim-drop-at, in AgentOptions.)
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <random>
#include <thread>

#include "engine/robots/robot_model.h"
#include "server/dispatch/arm_driver.h"

namespace dash::dispatch {

struct SimDriverOptions {
  JointVector initial;               ///< starting joint state (empty: all zeros)
  double speed = 1.0;                ///< trajectory time runs at this rate (0.5 = lagging at half speed)
  std::optional<double> stop_at;     ///< s after the start: the arm stops there and stays (no fault reported)
  bool refuse = false;               ///< refuse every goal (INVALID_GOAL)
  double step = 0.004;               ///< s per simulation step
  bool gripper = true;               ///< simulate a gripper (grasp closes it, release opens it)
  double pause_rate = 0.0;           ///< pauses per second of motion, at random (0: none)
  double pause_max = 0.0;            ///< s: each pause lasts uniformly 0 .. this
  double gripper_time = 0.0;         ///< s a gripper move takes (0: at once)
  double gripper_jitter = 0.0;       ///< s: each move takes gripper_time plus or minus up to this
  std::uint64_t seed = 1;            ///< of the pauses and the gripper's jitter
};

class SimDriver : public ArmDriver {
 public:
  SimDriver(const RobotModel& model, SimDriverOptions options);
  ~SimDriver() override;

  std::string kind() const override { return "sim"; }
  std::string model() const override { return model_name_; }
  std::vector<std::string> jointNames() const override { return joint_names_; }
  bool ready(std::string& detail) const override;
  DriverState state() const override;
  ResultCode load(const ArmTrajectory& trajectory, const GoalLimits& limits, std::string& message) override;
  void start(std::chrono::steady_clock::time_point at) override;
  void abort(const std::string& reason) override;
  DriverProgress progress() const override;
  std::string gripperState() const override;
  void shutdown() override;

  /// When abort() last stopped a loaded or running goal (for latency measurements in tests).
  std::optional<std::chrono::steady_clock::time_point> lastAbortTime() const;
  /// Gripper commands applied so far: (seconds after the start, action).
  std::vector<std::pair<double, GripperCommand::Action>> gripperLog() const;

 private:
  void loop();
  void stepLocked(std::chrono::steady_clock::time_point now, double dt);
  /// Fires the gripper commands the arm has reached (one move at a time) and ends a finished move.
  void stepGripperLocked(std::chrono::steady_clock::time_point now, double elapsed);

  std::string model_name_;
  std::vector<std::string> joint_names_;
  JointVector velocity_max_;
  SimDriverOptions options_;

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  bool stopping_ = false;
  JointVector q_;
  JointVector qd_;
  std::int64_t stamp_us_ = 0;  ///< when q_ was last computed
  ArmTrajectory goal_;
  GoalLimits limits_;
  DriverProgress progress_;
  bool started_ = false;
  std::chrono::steady_clock::time_point start_time_;
  std::size_t next_gripper_ = 0;
  bool gripper_closed_ = false;
  double tau_ = 0.0;  ///< how far along its goal the arm is (s of trajectory time)
  std::chrono::steady_clock::time_point paused_until_;
  std::optional<std::chrono::steady_clock::time_point> gripper_done_at_;  ///< a gripper move in progress
  bool gripper_target_closed_ = false;
  std::mt19937_64 rng_;
  std::vector<std::pair<double, GripperCommand::Action>> gripper_log_;
  std::optional<std::chrono::steady_clock::time_point> last_abort_;
  std::thread thread_;
};

}  // namespace dash::dispatch
