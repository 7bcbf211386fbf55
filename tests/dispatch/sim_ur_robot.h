#pragma once
// A simulated UR robot for the dispatch tests (never part of the product). It connects to the PC the
// way the External Control URCap and its program do: asks the script sender for the program with
// "request_program\n" (and checks it), connects the trajectory, script command and reverse sockets,
// then reads and decodes every reverse message and trajectory point byte for byte, executes the points
// in (speed-scaled) real time, stops when a reverse read times out, and answers each trajectory with
// 0 (success), 1 (cancelled) or 2 (failure). It also serves RTDE (timestamp, actual_q, actual_qd) so the PC side
// can read the joint state (and can stall it, as a real stream can stop while the socket stays open),
// and stops its program on MODE_STOPPED. Everything it received is recorded for the tests.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <deque>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/robots/joint_vector.h"
#include "server/dispatch/tcp_socket.h"
#include "server/dispatch/ur_protocol.h"
#include "sim_gripper.h"

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
  /// s: RTDE reports the commanded position this much later (servoj's look-ahead makes a real arm lag
  /// its target by a few tens of milliseconds); 0 = none.
  double tracking_delay = 0.0;
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
  /// The PC sent MODE_STOPPED: the program left its loop (when, steady microseconds; 0 = never).
  std::int64_t stoppedByPcAt() const;
  /// Stops (true) or resumes the RTDE data packages; the connection stays open. Returns when the last
  /// state sent before the stall was measured (steady microseconds).
  std::int64_t stallRtde(bool stall);
  int trajectoryResultsSent() const;
  JointVector q() const;
  /// RTDE handshake as seen: protocol version asked, output names asked.
  int rtdeVersionAsked() const;
  std::string rtdeOutputsAsked() const;

 private:
  void programLoop();
  // programLoop's steps: false when the program stops there.
  bool fetchProgram();
  bool connectProgramSockets();
  /// The next reverse message (the first read waits for as long as it takes, or until stop()).
  IoResult readReverse(std::uint8_t* buffer, std::size_t size, int read_timeout_ms);
  bool onReverseMessage(const ur::ReverseMessage& m, std::chrono::steady_clock::time_point now,
                        std::int32_t& control_mode);
  void rtdeLoop();
  void trajectoryLoop(int points, std::chrono::steady_clock::time_point started);
  void cancelTrajectory(bool always_answer);
  /// Runs one segment from `begin` (absolute schedule: delays do not add up); false if cancelled.
  bool runSegment(const JointVector& q_end, const JointVector& qd_end, double duration,
                  std::chrono::steady_clock::time_point begin);
  void sendResult(std::int32_t result);
  void halt(const std::string& why);
  /// The position RTDE reports: the commanded one, tracking_delay ago.
  JointVector reportedLocked(std::int64_t now_us) const;
  void recordLocked(std::int64_t t_us);

  SimUrRobotOptions options_;
  Socket rtde_listener_;
  int rtde_port_ = 0;
  Socket script_, trajectory_, command_, reverse_;
  std::mutex trajectory_write_;

  mutable std::mutex mutex_;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> cancel_{false};
  JointVector q_, qd_, spline_qd_;
  std::int64_t q_stamp_us_ = 0;  ///< when q_ was last computed (steady)
  std::int64_t epoch_us_ = 0;    ///< the robot controller's time 0 (RTDE timestamp)
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
  std::int64_t stopped_by_pc_us_ = 0;
  bool rtde_stalled_ = false;
  std::int64_t last_rtde_sent_us_ = 0;
  std::deque<std::pair<std::int64_t, JointVector>> history_;  ///< commanded positions, for tracking_delay
  int points_left_ = 0;
  bool trajectory_running_ = false;
  int rtde_version_ = 0;
  std::string rtde_outputs_;
  std::thread program_thread_, rtde_thread_, trajectory_thread_;
};

}  // namespace dash::dispatch::test
