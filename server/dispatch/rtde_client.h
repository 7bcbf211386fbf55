#pragma once
// A read-only RTDE client (UR's Real-Time Data Exchange, robot port 30004, protocol version 2): it
// subscribes to actual_q and actual_qd and keeps the latest values, reconnecting on its own. External
// Control carries no joint states back to the PC; RTDE is where UR's own driver reads them.
// Packets: uint16 size (header included) + uint8 type + payload, big-endian. Used here:
// 'V' request protocol version (uint16 2 -> uint8 accepted), 'O' setup outputs (double frequency +
// "actual_q,actual_qd" -> uint8 recipe id + "VECTOR6D,VECTOR6D"), 'S' start (-> uint8 accepted),
// 'U' data package (uint8 recipe id + the values); 'M' text messages are skipped.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "engine/robots/joint_vector.h"
#include "server/dispatch/tcp_socket.h"

namespace dash::dispatch {

namespace rtde {
inline constexpr std::uint8_t kRequestProtocolVersion = 'V';
inline constexpr std::uint8_t kTextMessage = 'M';
inline constexpr std::uint8_t kDataPackage = 'U';
inline constexpr std::uint8_t kSetupOutputs = 'O';
inline constexpr std::uint8_t kSetupInputs = 'I';
inline constexpr std::uint8_t kStart = 'S';
inline constexpr std::uint8_t kPause = 'P';
inline constexpr std::uint16_t kProtocolVersion = 2;
inline constexpr const char* kOutputs = "actual_q,actual_qd";
inline constexpr const char* kOutputTypes = "VECTOR6D,VECTOR6D";
}  // namespace rtde

struct RtdeOptions {
  std::string host;
  int port = 30004;
  double frequency = 125.0;  ///< Hz asked of the robot
  int timeout_ms = 1000;     ///< connect and handshake answers
  int reconnect_ms = 500;
};

class RtdeClient {
 public:
  explicit RtdeClient(RtdeOptions options);
  ~RtdeClient();
  RtdeClient(const RtdeClient&) = delete;
  RtdeClient& operator=(const RtdeClient&) = delete;

  struct State {
    bool connected = false;
    JointVector q;
    JointVector qd;
    std::int64_t received_us = 0;  ///< steady clock; 0 before the first package
  };
  State state() const;
  /// This machine's address on the connection to the robot ("" until connected).
  std::string localAddress() const;
  void stop();

 private:
  void loop();
  bool session(Socket& socket);

  RtdeOptions options_;
  mutable std::mutex mutex_;
  State state_;
  std::string local_address_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> fd_{-1};
  std::thread thread_;
};

}  // namespace dash::dispatch
