#pragma once
// A simulated UR robot for the dispatch tests (never part of the product). It connects to the PC the
// way the External Control URCap and its program do: asks the script sender for the program with
// "request_program\n" (and checks it), connects the trajectory, script command and reverse sockets,
// then reads and decodes every reverse message and trajectory point byte for byte, executes the points
// in (speed-scaled) real time, stops when a reverse read times out, and answers each trajectory with
// 0 (success), 1 (cancelled) or 2 (failure). It also serves RTDE (actual_q, actual_qd) so the PC side
// can read the joint state. Everything it received is recorded for the tests.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/robots/joint_vector.h"
#include "server/dispatch/tcp_socket.h"
#include "server/dispatch/ur_protocol.h"

namespace dash::dispatch::test {

struct SimUrRobotOptions {
  std::string pc_host = "127.0.0.1";
  int script_port = 0;
  int reverse_port = 0;
  int trajectory_port = 0;
  int script_command_port = 0;
  JointVector initial;         ///< 6 joints
  double speed_scaling = 1.0;  ///< the pendant's speed slider: segments take duration / speed_scaling
  double step = 0.002;         ///< control period (s)
  double rtde_frequency_cap = 500.0;
};

class SimUrRobot {
 public:
  explicit SimUrRobot(SimUrRobotOptions options);  ///< binds the RTDE port
  ~SimUrRobot();
  int rtdePort() const { return rtde_port_; }
  /// The PC's ports, when they are only known after construction (before start()).
  void setPcPorts(int script, int reverse, int trajectory, int script_command) {
    options_.script_port = script;
    options_.reverse_port = reverse;
    options_.trajectory_port = trajectory;
    options_.script_command_port = script_command;
  }
  void start();
  void stop();

  struct ReceivedPoint {
    ur::PointMessage raw;
    JointVector q, qd;
    double duration = 0.0;
    std::int64_t received_us = 0;
  };
  struct ReverseRecord {
    ur::ReverseMessage message;
    std::int64_t received_us = 0;
  };

  bool programConnected() const;  ///< all three sockets connected, main loop running
  std::string program() const;
  /// The program's checks: markers, the ports and host filled in. Empty when fine.
  std::string programProblem() const;
  std::vector<ReceivedPoint> points() const;
  std::vector<ReverseRecord> commands() const;  ///< START and CANCEL messages (not keep-alives)
  std::vector<std::int64_t> cancelTimes() const;
  std::vector<std::int32_t> resultsSent() const;
  int keepalives() const;
  double maxReverseGap() const;  ///< s: the longest wait between two reverse messages while connected
  bool halted() const;
  std::string haltReason() const;
  JointVector q() const;
  /// RTDE handshake as seen: protocol version asked, output names asked.
  int rtdeVersionAsked() const;
  std::string rtdeOutputsAsked() const;

 private:
  void programLoop();
  void rtdeLoop();
  void trajectoryLoop(int points);
  void cancelTrajectory(bool always_answer);
  /// Runs one segment from `begin` (absolute schedule: delays do not add up); false if cancelled.
  bool runSegment(const JointVector& q_end, const JointVector& qd_end, double duration,
                  std::chrono::steady_clock::time_point begin);
  void sendResult(std::int32_t result);
  void halt(const std::string& why);

  SimUrRobotOptions options_;
  Socket rtde_listener_;
  int rtde_port_ = 0;
  Socket script_, trajectory_, command_, reverse_;
  std::mutex trajectory_write_;

  mutable std::mutex mutex_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> cancel_{false};
  JointVector q_, qd_, spline_qd_;
  std::string program_;
  bool connected_ = false;
  std::vector<ReceivedPoint> points_;
  std::vector<ReverseRecord> commands_;
  std::vector<std::int64_t> cancel_times_;
  std::vector<std::int32_t> results_;
  int keepalives_ = 0;
  double max_gap_ = 0.0;
  bool halted_ = false;
  std::string halt_reason_;
  int points_left_ = 0;
  bool trajectory_running_ = false;
  int rtde_version_ = 0;
  std::string rtde_outputs_;
  std::thread program_thread_, rtde_thread_, trajectory_thread_;
};

/// A simulated Robotiq gripper URCap socket: answers "ack" to SET commands, "POS n" / "STA 3" to GET.
class SimGripper {
 public:
  SimGripper();  ///< binds 127.0.0.1 on a free port
  ~SimGripper();
  int port() const { return port_; }
  struct Command {
    std::string line;
    std::int64_t received_us = 0;
  };
  std::vector<Command> commands() const;
  bool activated() const;

 private:
  void loop();
  Socket listener_;
  int port_ = 0;
  mutable std::mutex mutex_;
  std::vector<Command> commands_;
  bool activated_ = false;
  int position_ = 0;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace dash::dispatch::test
