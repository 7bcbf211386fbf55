#pragma once
// Client of the ASCII socket that Robotiq's gripper URCap serves on the robot (port 63352), spoken the
// way Robotiq's own clients speak it: one command per line; a SET (several variables may share one
// line: "SET POS 255 SPE 255 FOR 100 GTO 1") is answered with the 3 bytes "ack" and no newline (their
// Python client checks `data == b'ack'` on one recv, their URScript reads exactly 3 bytes); a GET is
// answered "VAR value" ("STA 3"), with or without a newline. External Control's script command socket
// has no gripper command, so grasp and release go this way.
//
// Activation (Robotiq's activate()): reset first (SET ACT 0, SET ATR 0, wait for STA 0), then SET ACT 1
// and wait for STA 3. A move (move_and_wait_for_pos()): POS, SPE and FOR with GTO 1 in one SET (at
// power-on SPE and FOR are 0: slowest and weakest), wait until PRE echoes the position, then poll OBJ
// until it is not 0 (moving).
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "server/dispatch/tcp_socket.h"

namespace dash::dispatch {

namespace robotiq {
inline constexpr int kPort = 63352;
inline constexpr int kOpen = 0;      ///< POS 0: fully open
inline constexpr int kClosed = 255;  ///< POS 255: fully closed
inline constexpr int kActive = 3;    ///< STA 3: activation completed

/// OBJ: the object detection status after a move.
enum class ObjectStatus {
  kMoving = 0,          ///< still moving towards the requested position
  kStoppedOpening = 1,  ///< stopped by an object while opening
  kStoppedClosing = 2,  ///< stopped by an object while closing: a part is held
  kAtPosition = 3,      ///< reached the requested position: no object (a missed grasp when closing)
};
const char* objectStatusText(int obj);
}  // namespace robotiq

struct RobotiqTimings {
  int answer_timeout_ms = 1000;       ///< for each answer
  int activation_timeout_ms = 10000;  ///< reset plus activation (a Hand-E takes a few seconds)
  int move_timeout_ms = 5000;         ///< from GTO 1 until OBJ is not 0
  int poll_ms = 10;                   ///< between GETs while waiting
  int value_grace_ms = 2;             ///< wait for more digits of a GET answer that came without newline
};

class RobotiqGripper {
 public:
  explicit RobotiqGripper(RobotiqTimings timings = {}) : timings_(timings) {}

  /// Connects (no command sent). False with `error` on failure.
  bool connect(const std::string& host, int port, int connect_timeout_ms, std::string& error);
  bool connected() const;
  void close();

  /// Resets and activates; returns when STA is 3. `cancelled` (may be empty) ends the waits early.
  bool activate(const std::function<bool()>& cancelled, std::string& error);

  struct MoveResult {
    bool ok = false;   ///< the move was commanded and ended (OBJ not 0); `error` otherwise
    int obj = 0;       ///< robotiq::ObjectStatus as a number
    int position = 0;  ///< POS at the end
    std::string error;
  };
  /// Moves to `position` (0 open .. 255 closed) with speed and force 0..255 and waits for the end.
  MoveResult move(int position, int speed, int force, const std::function<bool()>& cancelled);

  /// "SET A 1 B 2 ..." answered "ack". False with `error` otherwise (the connection is then closed).
  bool set(const std::vector<std::pair<std::string, int>>& vars, std::string& error);
  /// "GET VAR" answered "VAR n": n, or nullopt with `error` (the connection is then closed).
  std::optional<int> get(const std::string& var, std::string& error);

 private:
  /// Sends `line` + "\n" and reads the answer: exactly "ack" (ack = true) or "VAR n".
  bool exchange(const std::string& line, bool ack, std::string& answer, std::string& error);
  bool readAck(std::string& answer, std::string& error);
  bool readValue(std::string& answer, std::string& error);
  /// Reads what is there (waiting up to timeout_ms for the first byte); false if closed or nothing came.
  IoResult fill(int timeout_ms);
  bool waitFor(const std::string& var, int value, int timeout_ms, const std::function<bool()>& cancelled,
               std::string& error);
  void dropLocked();

  RobotiqTimings timings_;
  mutable std::mutex mutex_;
  Socket socket_;
  std::string pending_;  ///< bytes received and not yet consumed
};

}  // namespace dash::dispatch
