#pragma once
// A read-only RTDE client (UR's Real-Time Data Exchange, robot port 30004, protocol version 2): it
// subscribes to timestamp, actual_q and actual_qd and keeps the latest values, reconnecting on its own.
// External Control carries no joint states back to the PC; RTDE is where UR's own driver reads them.
// Each state is stamped with when the robot measured it, on this PC's steady clock: the robot's
// timestamp plus the smallest (receive time - timestamp) seen lately, so a package that waited for
// this process to be scheduled is not taken for a later measurement.
// Packets: uint16 size (header included) + uint8 type + payload, big-endian. Used here:
// 'V' request protocol version (uint16 2 -> uint8 accepted), 'O' setup outputs (double frequency +
// "timestamp,actual_q,actual_qd" -> uint8 recipe id + "DOUBLE,VECTOR6D,VECTOR6D"), 'S' start (-> uint8 accepted),
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
inline constexpr const char* kOutputs = "timestamp,actual_q,actual_qd";
inline constexpr const char* kOutputTypes = "DOUBLE,VECTOR6D,VECTOR6D";
inline constexpr std::size_t kDataSize = 1 + 8 + 12 * 8;  ///< recipe id, timestamp, 12 doubles
/// s over which the smallest receive delay maps robot time to this PC's (clock drift is ppm).
inline constexpr double kClockWindow = 2.0;
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
    std::int64_t measured_us = 0;  ///< steady clock: when the robot measured q (<= received_us)
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
  // Robot time -> steady clock: the smallest (receive - robot time) of the current and last window.
  double best_offset_ = 0.0, window_best_ = 0.0;
  std::int64_t window_start_us_ = 0;
  bool have_offset_ = false;
  std::thread thread_;
};

}  // namespace dash::dispatch
