#pragma once
// Client of the ASCII socket that Robotiq's gripper URCap serves on the robot (port 63352): one
// command per line, each answered "ack" (GET commands answer their value). External Control's script
// command socket has no gripper command, so grasp and release go this way.
#include <mutex>
#include <string>

#include "server/dispatch/tcp_socket.h"

namespace dash::dispatch {

namespace robotiq {
inline constexpr int kPort = 63352;
inline constexpr int kOpen = 0;      ///< SET POS 0: fully open
inline constexpr int kClosed = 255;  ///< SET POS 255: fully closed
}  // namespace robotiq

class RobotiqGripper {
 public:
  /// Connects and activates: "SET ACT 1", "SET GTO 1". False with `error` on failure.
  bool connect(const std::string& host, int port, int timeout_ms, std::string& error);
  bool connected() const;
  /// "SET POS n" (0 open .. 255 closed); false with `error` unless answered "ack".
  bool setPosition(int position, std::string& error);
  /// Sends one line, returns the answer line.
  bool command(const std::string& line, std::string& answer, std::string& error);
  void close();

 private:
  bool expectAck(const std::string& line, std::string& error);
  mutable std::mutex mutex_;
  Socket socket_;
  int timeout_ms_ = 1000;
};

}  // namespace dash::dispatch
