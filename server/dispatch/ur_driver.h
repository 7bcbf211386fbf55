#pragma once
// A real UR arm (UR5e) through External Control (ur_protocol.h): this process is the PC side. It
// listens on the reverse, script sender, trajectory and script command ports (one client each), serves
// the program on request_program, reads joint states over RTDE (rtde_client.h), and runs a goal in
// FORWARD mode: at the start time one START message with the point count, then every point as a cubic
// SPLINE (or MOVEJ) point on the trajectory socket, NOOP keep-alives well within the read timeout
// until the robot answers, CANCEL on abort, MODE_STOPPED before it closes the reverse socket. Grasp and
// release become Robotiq URCap moves at their times (robotiq_gripper.h); a grasp that closes on nothing
// (OBJ 3) fails the goal. It fails safe: a goal fails (and the robot gets CANCEL) when the RTDE joint
// state is older than the staleness bound, when the gripper stops answering (checked before arming and
// every gripper_poll while connected), or when the robot program disconnects.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/robots/robot_model.h"
#include "server/dispatch/arm_driver.h"
#include "server/dispatch/robotiq_gripper.h"
#include "server/dispatch/rtde_client.h"
#include "server/dispatch/tcp_socket.h"
#include "server/dispatch/ur_protocol.h"

namespace dash::dispatch {

struct UrDriverOptions {
  std::string robot_ip;             ///< the robot: RTDE and (by default) the gripper
  std::string host_ip;              ///< this PC as the robot reaches it; empty: the address RTDE connected from
  std::string listen_host = "0.0.0.0";
  int reverse_port = 50001;
  int script_port = 50002;
  int trajectory_port = 50003;
  int script_command_port = 50004;
  int rtde_port = 30004;
  double rtde_frequency = 500.0;    ///< Hz: a UR e-series streams at up to 500 Hz (CB3: 125)
  /// s: a joint state older than this is no measured state, and a goal in progress fails at once.
  /// 0: kStalePeriods RTDE periods plus kStaleMargin (26 ms at 500 Hz).
  double state_stale_after = 0.0;
  int read_timeout_ms = 100;        ///< sent in every reverse message: the robot stops if the next is later
  int keepalive_ms = 10;            ///< period of reverse messages (well under read_timeout_ms)
  ur::PointType point_type = ur::PointType::kSpline;
  bool gripper = false;             ///< a Robotiq gripper through its URCap socket
  std::string gripper_host;         ///< empty: robot_ip
  int gripper_port = robotiq::kPort;
  int gripper_speed = 255;          ///< SPE of every move (0 slowest .. 255)
  int gripper_force = 255;          ///< FOR of every move (0 weakest .. 255)
  RobotiqTimings gripper_timings;   ///< answer, activation and move timeouts
  double gripper_poll = 0.25;       ///< s between connection checks (GET STA) while no move runs
  double cancel_timeout = 1.0;      ///< s to wait for the robot's CANCELED answer
};

inline constexpr int kStalePeriods = 3;
inline constexpr double kStaleMargin = 0.02;  ///< s on top of the periods: this PC's scheduling jitter

class UrDriver : public ArmDriver {
 public:
  UrDriver(const RobotModel& model, UrDriverOptions options);  ///< throws InputError if a port cannot be bound
  ~UrDriver() override;

  std::string kind() const override { return "ur"; }
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

  /// The ports actually bound (a requested 0 picks a free one).
  struct Ports {
    int reverse = 0, script = 0, trajectory = 0, script_command = 0;
  };
  Ports ports() const { return ports_; }

 private:
  enum class Phase { kIdle, kArmed, kWaitingStart, kSent, kCancelling, kGoalCheck };
  /// One of the four servers: its listening socket and its one client.
  struct Endpoint {
    std::string name;
    Socket listener;
    Socket client;
    mutable std::mutex write_mutex;  ///< guards client for writes and replacement
    std::string inbox;       ///< bytes read so far (script sender, trajectory results)
  };

  void ioLoop();
  void controlLoop();
  void checkGoalLocked(std::chrono::steady_clock::time_point now);
  // The gripper (ur_driver_gripper.cpp).
  void gripperLoop();
  bool connectGripper();
  void runGripperMove(int position, std::uint64_t goal_seq);
  void pollGripper();
  /// Whether the gripper answers GET STA with 3 now; `error` says why not.
  bool gripperAnswers(std::string& error);
  double staleBound() const;
  void handleReadable(Endpoint& endpoint);
  void dropClient(Endpoint& endpoint, const std::string& why);
  void handleResult(std::int32_t result);
  bool sendReverse(const ur::ReverseMessage& message);
  bool sendPoints(const std::vector<ur::PointMessage>& points);
  void failLocked(ArmStatus status, ResultCode code, const std::string& message);
  bool connectedLocked(const Endpoint& endpoint) const;
  bool robotConnected() const;

  std::string model_name_;
  std::vector<std::string> joint_names_;
  JointVector velocity_max_;
  UrDriverOptions options_;
  Ports ports_;

  Endpoint reverse_, script_, trajectory_, command_;
  std::unique_ptr<RtdeClient> rtde_;
  RobotiqGripper gripper_;

  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::atomic<bool> stopping_{false};
  Phase phase_ = Phase::kIdle;
  std::chrono::steady_clock::time_point next_gripper_poll_;
  DriverProgress progress_;
  ArmTrajectory goal_;
  GoalLimits limits_;
  std::vector<ur::PointMessage> points_;
  std::chrono::steady_clock::time_point start_at_;
  std::chrono::steady_clock::time_point deadline_;  ///< cancel answer or goal check
  std::string abort_reason_;
  // Gripper schedule (absolute times) and state.
  std::vector<std::pair<std::chrono::steady_clock::time_point, int>> gripper_plan_;
  std::size_t gripper_next_ = 0;
  bool gripper_moving_ = false;   ///< a move of this goal is in progress
  bool gripper_ready_ = false;    ///< connected, activated, and answered its last check
  bool gripper_activated_ = false;  ///< activated once in this process (a reconnection skips the reset)
  bool gripper_closed_ = false;
  std::string gripper_error_;
  std::atomic<std::uint64_t> goal_seq_{0};  ///< changes whenever a goal is loaded, ends or is aborted

  std::thread io_thread_, control_thread_, gripper_thread_;
};

}  // namespace dash::dispatch
