#include "server/dispatch/rtde_client.h"

#include <sys/socket.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <vector>

#include "server/dispatch/dispatch_types.h"

namespace dash::dispatch {

namespace {

bool sendPacket(int fd, std::uint8_t type, const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> packet(3 + payload.size());
  const auto size = static_cast<std::uint16_t>(packet.size());
  packet[0] = static_cast<std::uint8_t>(size >> 8);
  packet[1] = static_cast<std::uint8_t>(size);
  packet[2] = type;
  std::copy(payload.begin(), payload.end(), packet.begin() + 3);
  return writeAll(fd, packet.data(), packet.size());
}

/// Reads one packet; kTimeout/kClosed on failure.
IoResult readPacket(int fd, std::uint8_t& type, std::vector<std::uint8_t>& payload, int timeout_ms) {
  std::uint8_t header[3];
  IoResult r = readExact(fd, header, 3, timeout_ms);
  if (r != IoResult::kOk) return r;
  const std::uint16_t size = static_cast<std::uint16_t>((header[0] << 8) | header[1]);
  if (size < 3) return IoResult::kClosed;
  type = header[2];
  payload.resize(size - 3u);
  return payload.empty() ? IoResult::kOk : readExact(fd, payload.data(), payload.size(), timeout_ms);
}

/// The next packet of `type`, skipping text messages.
bool expect(int fd, std::uint8_t type, std::vector<std::uint8_t>& payload, int timeout_ms) {
  for (;;) {
    std::uint8_t got = 0;
    if (readPacket(fd, got, payload, timeout_ms) != IoResult::kOk) return false;
    if (got == type) return true;
    if (got != rtde::kTextMessage) return false;
  }
}

}  // namespace

RtdeClient::RtdeClient(RtdeOptions options) : options_(std::move(options)) {
  thread_ = std::thread([this] { loop(); });
}

RtdeClient::~RtdeClient() { stop(); }

void RtdeClient::stop() {
  stopping_ = true;
  const int fd = fd_.load();
  if (fd >= 0) ::shutdown(fd, SHUT_RDWR);
  if (thread_.joinable()) thread_.join();
}

RtdeClient::State RtdeClient::state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

std::string RtdeClient::localAddress() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return local_address_;
}

void RtdeClient::loop() {
  while (!stopping_) {
    Socket socket = connectTcp(options_.host, options_.port, options_.timeout_ms);
    if (socket.valid()) {
      fd_ = socket.fd();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        local_address_ = dispatch::localAddress(socket);
      }
      session(socket);
      fd_ = -1;
      std::lock_guard<std::mutex> lock(mutex_);
      state_.connected = false;
    }
    for (int waited = 0; waited < options_.reconnect_ms && !stopping_; waited += 20) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
}


bool RtdeClient::session(Socket& socket) {
  const int fd = socket.fd();
  std::vector<std::uint8_t> payload;
  // Protocol version 2.
  if (!sendPacket(fd, rtde::kRequestProtocolVersion, {0, static_cast<std::uint8_t>(rtde::kProtocolVersion)}) ||
      !expect(fd, rtde::kRequestProtocolVersion, payload, options_.timeout_ms) || payload.empty() || payload[0] != 1) {
    return false;
  }
  // Outputs: actual_q, actual_qd at the asked frequency.
  std::vector<std::uint8_t> setup(8);
  putDouble(setup.data(), options_.frequency);
  const std::string names = rtde::kOutputs;
  setup.insert(setup.end(), names.begin(), names.end());
  if (!sendPacket(fd, rtde::kSetupOutputs, setup) || !expect(fd, rtde::kSetupOutputs, payload, options_.timeout_ms) ||
      payload.empty()) {
    return false;
  }
  const std::uint8_t recipe = payload[0];
  const std::string types(payload.begin() + 1, payload.end());
  if (types != rtde::kOutputTypes) return false;  // e.g. NOT_FOUND
  if (!sendPacket(fd, rtde::kStart, {}) || !expect(fd, rtde::kStart, payload, options_.timeout_ms) ||
      payload.empty() || payload[0] != 1) {
    return false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    state_.connected = true;
  }
  have_offset_ = false;  // a new session may be a restarted controller: a new time base
  while (!stopping_) {
    std::uint8_t type = 0;
    const IoResult r = readPacket(fd, type, payload, options_.timeout_ms);
    if (r != IoResult::kOk) return false;
    if (type != rtde::kDataPackage || payload.size() != rtde::kDataSize || payload[0] != recipe) continue;
    const std::int64_t received = steadyMicros();
    const double robot_time = getDouble(payload.data() + 1);
    JointVector q(6), qd(6);
    for (int j = 0; j < 6; ++j) {
      q[j] = getDouble(payload.data() + 9 + 8 * j);
      qd[j] = getDouble(payload.data() + 57 + 8 * j);
    }
    const double offset = received * 1e-6 - robot_time;
    if (!have_offset_ || received - window_start_us_ > static_cast<std::int64_t>(rtde::kClockWindow * 1e6)) {
      best_offset_ = have_offset_ ? std::min(window_best_, offset) : offset;
      window_best_ = offset;
      window_start_us_ = received;
      have_offset_ = true;
    }
    window_best_ = std::min(window_best_, offset);
    best_offset_ = std::min(best_offset_, offset);
    const auto measured = static_cast<std::int64_t>(std::llround((robot_time + best_offset_) * 1e6));
    std::lock_guard<std::mutex> lock(mutex_);
    state_.q = q;
    state_.qd = qd;
    state_.received_us = received;
    state_.measured_us = std::isfinite(robot_time) ? std::min(measured, received) : received;
  }
  return true;
}

}  // namespace dash::dispatch
