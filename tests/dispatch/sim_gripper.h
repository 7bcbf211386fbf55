#pragma once
// A simulated Robotiq gripper URCap socket for the dispatch tests (never part of the product), beside
// the simulated UR robot (sim_ur_robot.h).
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/dispatch/tcp_socket.h"

namespace dash::dispatch::test {

struct SimGripperOptions {
  double activation_delay = 0.3;  ///< s from SET ACT 1 to STA 3 (a real Hand-E: a few seconds)
  double stroke_time = 0.2;       ///< s for a full stroke (0 .. 255)
  bool object = true;             ///< a part between the fingers: closing stops on it (OBJ 2), else OBJ 3
  int object_position = 200;      ///< where closing fingers meet the part
};

/// A simulated Robotiq gripper URCap socket, answering as the real one: a SET with the 3 bytes "ack"
/// (no newline), a GET with "VAR value" (no newline). STA goes 0 -> 1 -> 3 activation_delay after
/// SET ACT 1; moves (POS/SPE/FOR with GTO 1, ignored before activation) take time, PRE echoes the
/// requested position, OBJ is 0 while moving and 2 or 3 at the end.
class SimGripper {
 public:
  explicit SimGripper(SimGripperOptions options = {});  ///< binds 127.0.0.1 on a free port
  ~SimGripper();
  int port() const { return port_; }
  struct Command {
    std::string line;
    std::string answer;
    std::int64_t received_us = 0;
  };
  std::vector<Command> commands() const;
  /// Only the SET lines, in order.
  std::vector<std::string> sets() const;
  bool activated() const;
  void setObjectPresent(bool present);
  /// The URCap dies: its connection closes and it takes no new one.
  void kill();

 private:
  void loop();
  std::string answerLocked(const std::string& line, std::int64_t now_us);
  int positionLocked(std::int64_t now_us, int* obj) const;

  SimGripperOptions options_;
  Socket listener_;
  int port_ = 0;
  mutable std::mutex mutex_;
  std::vector<Command> commands_;
  int act_ = 0;
  std::int64_t act_us_ = 0;        ///< when SET ACT 1 came
  int requested_ = 0;              ///< PRE
  int from_ = 0;                   ///< position when the move began
  std::int64_t move_us_ = 0;       ///< when the move began (0: none yet)
  bool moved_ = false;
  std::atomic<bool> stopping_{false};
  std::atomic<bool> dead_{false};
  std::thread thread_;
};

}  // namespace dash::dispatch::test
