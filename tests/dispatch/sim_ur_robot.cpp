#include "sim_ur_robot.h"

#include <sys/socket.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "server/dispatch/dispatch_types.h"
#include "server/dispatch/rtde_client.h"

namespace dash::dispatch::test {

using SteadyClock = std::chrono::steady_clock;

namespace {

constexpr int kConnectRetryMs = 20;
constexpr int kFirstPointTimeoutMs = 500;
constexpr int kNextPointTimeoutMs = 100;

bool sendRtde(int fd, std::uint8_t type, const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> packet(3 + payload.size());
  const auto size = static_cast<std::uint16_t>(packet.size());
  packet[0] = static_cast<std::uint8_t>(size >> 8);
  packet[1] = static_cast<std::uint8_t>(size);
  packet[2] = type;
  std::copy(payload.begin(), payload.end(), packet.begin() + 3);
  return writeAll(fd, packet.data(), packet.size());
}

Socket connectRetry(const std::string& host, int port, const std::atomic<bool>& stopping) {
  while (!stopping) {
    Socket s = connectTcp(host, port, 200);
    if (s.valid()) return s;
    std::this_thread::sleep_for(std::chrono::milliseconds(kConnectRetryMs));
  }
  return Socket();
}

JointVector hermite(const JointVector& q0, const JointVector& v0, const JointVector& q1, const JointVector& v1, double T,
                    double s) {
  const double s2 = s * s, s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * q0 + (s3 - 2 * s2 + s) * T * v0 + (-2 * s3 + 3 * s2) * q1 + (s3 - s2) * T * v1;
}

}  // namespace

SimUrRobot::SimUrRobot(SimUrRobotOptions options) : options_(std::move(options)), epoch_us_(steadyMicros()) {
  q_ = options_.initial.size() == 6 ? options_.initial : JointVector::Zero(6);
  qd_ = JointVector::Zero(6);
  spline_qd_ = JointVector::Zero(6);
  rtde_listener_ = listenTcp("127.0.0.1", 0);
  rtde_port_ = boundPort(rtde_listener_);
}

SimUrRobot::~SimUrRobot() { stop(); }

void SimUrRobot::start() {
  rtde_thread_ = std::thread([this] { rtdeLoop(); });
  program_thread_ = std::thread([this] { programLoop(); });
}

void SimUrRobot::stop() {
  if (stopping_.exchange(true)) return;
  cancel_ = true;
  for (Socket* s : {&script_, &trajectory_, &command_, &reverse_}) s->shutdown();
  if (program_thread_.joinable()) program_thread_.join();
  if (trajectory_thread_.joinable()) trajectory_thread_.join();
  if (rtde_thread_.joinable()) rtde_thread_.join();
}

void SimUrRobot::halt(const std::string& why) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!halted_) {
    halted_ = true;
    halt_reason_ = why;
  }
  connected_ = false;
}

void SimUrRobot::programLoop() {
  if (!fetchProgram() || !connectProgramSockets()) return;
  // 3. The control loop: one reverse message at a time, each one's timeout governs the next read.
  int read_timeout_ms = 0;  // the first read blocks
  auto control_mode = static_cast<std::int32_t>(-1);
  bool first = true;
  auto last = SteadyClock::now();
  while (!stopping_) {
    std::uint8_t buffer[4 * ur::kReverseMessageInts];
    const IoResult r = readReverse(buffer, sizeof buffer, read_timeout_ms);
    if (stopping_) break;
    if (r == IoResult::kTimeout) {
      halt("no reverse message within " + std::to_string(read_timeout_ms) + " ms");
      break;
    }
    if (r == IoResult::kClosed) {
      halt("the PC closed the reverse socket");
      break;
    }
    const auto now = SteadyClock::now();
    const ur::ReverseMessage m = ur::decodeReverse(buffer);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!first) max_gap_ = std::max(max_gap_, std::chrono::duration<double>(now - last).count());
    }
    first = false;
    last = now;
    read_timeout_ms = m[0];
    if (!onReverseMessage(m, now, control_mode)) break;
  }
  cancel_ = true;
  if (trajectory_thread_.joinable()) trajectory_thread_.join();
  for (Socket* s : {&trajectory_, &command_, &reverse_}) s->shutdown();
  std::lock_guard<std::mutex> lock(mutex_);
  connected_ = false;
  qd_.setZero();
}

bool SimUrRobot::fetchProgram() {
  // 1. The URCap asks the script sender for the program.
  script_ = connectRetry(options_.pc_host, options_.script_port, stopping_);
  if (stopping_) return false;
  const std::string request = ur::kProgramRequest;
  writeAll(script_.fd(), request.data(), request.size());
  std::string text;
  const std::string end = std::string(ur::kProgramEndMarker) + "\n";
  const auto give_up = SteadyClock::now() + std::chrono::seconds(3);
  while (text.find(end) == std::string::npos && SteadyClock::now() < give_up && !stopping_) {
    if (!waitReadable(script_.fd(), 50)) continue;
    char buffer[4096];
    const ssize_t k = ::recv(script_.fd(), buffer, sizeof buffer, 0);
    if (k <= 0) break;
    text.append(buffer, static_cast<std::size_t>(k));
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    program_ = text;
  }
  if (text.find(end) == std::string::npos) {
    halt("no complete program from the script sender");
    return false;
  }
  return true;
}

bool SimUrRobot::connectProgramSockets() {
  // 2. The program connects its sockets: trajectory, script command, reverse (External Control's order).
  trajectory_ = connectRetry(options_.pc_host, options_.trajectory_port, stopping_);
  command_ = connectRetry(options_.pc_host, options_.script_command_port, stopping_);
  reverse_ = connectRetry(options_.pc_host, options_.reverse_port, stopping_);
  if (stopping_) return false;
  std::lock_guard<std::mutex> lock(mutex_);
  connected_ = true;
  return true;
}

IoResult SimUrRobot::readReverse(std::uint8_t* buffer, std::size_t size, int read_timeout_ms) {
  if (read_timeout_ms != 0) return readExact(reverse_.fd(), buffer, size, read_timeout_ms);
  while (!stopping_ && !waitReadable(reverse_.fd(), 50)) {
  }
  if (stopping_) return IoResult::kClosed;  // the caller sees stopping_ first
  return readExact(reverse_.fd(), buffer, size, 1000);
}

bool SimUrRobot::onReverseMessage(const ur::ReverseMessage& m, SteadyClock::time_point now,
                                  std::int32_t& control_mode) {
  const std::int32_t mode = m[7];
  if (mode == static_cast<std::int32_t>(ur::ControlMode::kStopped)) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopped_by_pc_us_ = steadyMicros();
    }
    if (trajectory_thread_.joinable()) cancelTrajectory(false);
    return false;  // the program leaves its control loop, stops the arm and closes its sockets
  }
  const auto forward = static_cast<std::int32_t>(ur::ControlMode::kForward);
  if (control_mode == forward && mode != forward) cancelTrajectory(false);
  control_mode = mode;
  const auto action = static_cast<ur::TrajectoryAction>(m[1]);
  if (mode == forward && action == ur::TrajectoryAction::kStart) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      commands_.push_back({m, steadyMicros()});
    }
    if (trajectory_thread_.joinable()) cancelTrajectory(false);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      points_left_ = m[2];
      trajectory_running_ = true;
      q_stamp_us_ = steadyMicros();
    }
    trajectory_thread_ = std::thread([this, n = m[2], at = now] { trajectoryLoop(n, at); });
  } else if (mode == forward && action == ur::TrajectoryAction::kCancel) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      commands_.push_back({m, steadyMicros()});
      cancel_times_.push_back(steadyMicros());
    }
    cancelTrajectory(true);
  } else {
    std::lock_guard<std::mutex> lock(mutex_);
    ++keepalives_;
  }
  return true;
}

void SimUrRobot::cancelTrajectory(bool always_answer) {
  bool had_points = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    had_points = points_left_ > 0;
  }
  cancel_ = true;
  if (trajectory_thread_.joinable()) trajectory_thread_.join();
  cancel_ = false;
  // Read away the points that were sent but not executed.
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (points_left_ <= 0) break;
      --points_left_;
    }
    std::uint8_t buffer[4 * ur::kPointMessageInts];
    if (readExact(trajectory_.fd(), buffer, sizeof buffer, kNextPointTimeoutMs) != IoResult::kOk) {
      std::lock_guard<std::mutex> lock(mutex_);
      points_left_ = 0;
      break;
    }
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    qd_.setZero();
    trajectory_running_ = false;
  }
  if (always_answer || had_points) sendResult(static_cast<std::int32_t>(ur::TrajectoryResult::kCancelled));
}

bool SimUrRobot::runSegment(const JointVector& q_end, const JointVector& qd_end, double duration,
                            SteadyClock::time_point begin) {
  JointVector q0, v0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    q0 = q_;
    v0 = spline_qd_;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    recordLocked(steadyMicros());
  }
  const double scale = options_.speed_scaling;
  const double T = duration / scale;
  const auto step = std::chrono::microseconds(static_cast<std::int64_t>(options_.step * 1e6));
  for (auto next = begin + step;; next += step) {
    std::this_thread::sleep_until(next);
    if (cancel_ || stopping_) return false;
    const double t = std::chrono::duration<double>(SteadyClock::now() - begin).count();
    const double s = std::min(t / T, 1.0);
    const JointVector q = hermite(q0, v0 * scale, q_end, qd_end * scale, T, s);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      qd_ = (q - q_) / options_.step;
      q_ = q;
      q_stamp_us_ = steadyMicros();
      recordLocked(steadyMicros());
    }
    if (s >= 1.0) break;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  q_ = q_end;
  q_stamp_us_ = steadyMicros();
  spline_qd_ = qd_end;
  recordLocked(steadyMicros());
  return true;
}

void SimUrRobot::recordLocked(std::int64_t t_us) {
  if (options_.tracking_delay <= 0.0) return;
  history_.emplace_back(t_us, q_);
  const auto keep = static_cast<std::int64_t>((options_.tracking_delay + 1.0) * 1e6);
  while (history_.size() > 2 && history_[1].first < t_us - keep) history_.pop_front();
}

JointVector SimUrRobot::reportedLocked(std::int64_t now_us) const {
  if (options_.tracking_delay <= 0.0 || history_.empty()) return q_;
  const std::int64_t at = now_us - static_cast<std::int64_t>(options_.tracking_delay * 1e6);
  if (at >= history_.back().first) return q_;
  for (auto it = history_.rbegin(); it != history_.rend(); ++it) {
    if (it->first <= at) return it->second;
  }
  return history_.front().second;
}

void SimUrRobot::trajectoryLoop(int /*points*/, SteadyClock::time_point started) {
  auto result = ur::TrajectoryResult::kSuccess;
  bool first = true;
  SteadyClock::time_point segment_begin{};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    spline_qd_.setZero();
  }
  for (;;) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (points_left_ <= 0) break;
    }
    if (cancel_ || stopping_) return;
    std::uint8_t buffer[4 * ur::kPointMessageInts];
    const IoResult r = readExact(trajectory_.fd(), buffer, sizeof buffer, first ? kFirstPointTimeoutMs : kNextPointTimeoutMs);
    if (cancel_ || stopping_) return;
    if (r != IoResult::kOk) {
      result = ur::TrajectoryResult::kFailure;
      break;
    }
    ReceivedPoint p;
    p.raw = ur::decodePoint(buffer);
    p.q = JointVector(6);
    p.qd = JointVector(6);
    for (int j = 0; j < 6; ++j) {
      p.q[j] = p.raw[static_cast<std::size_t>(j)] / ur::kMultJointState;
      p.qd[j] = p.raw[static_cast<std::size_t>(6 + j)] / ur::kMultJointState;
    }
    p.duration = p.raw[18] / ur::kMultTime;
    p.received_us = steadyMicros();
    JointVector current;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --points_left_;
      points_.push_back(p);
      current = q_;
    }
    if (first) segment_begin = started;  // the motion starts on START (its points follow at once)
    const auto type = static_cast<ur::PointType>(p.raw[20]);
    bool ok = true;
    if (type == ur::PointType::kSpline && p.raw[19] == static_cast<std::int32_t>(ur::SplineType::kCubic)) {
      if (p.duration <= 0.0) {
        if (!(first && maxAbsDifference(p.q, current) < 0.01)) result = ur::TrajectoryResult::kCancelled;
      } else {
        ok = runSegment(p.q, p.qd, p.duration, segment_begin);
        segment_begin += std::chrono::microseconds(static_cast<std::int64_t>(p.duration / options_.speed_scaling * 1e6));
      }
    } else if (type == ur::PointType::kMovej) {
      {
        std::lock_guard<std::mutex> lock(mutex_);
        spline_qd_.setZero();
      }
      ok = runSegment(p.q, JointVector::Zero(6), p.duration, segment_begin);
      segment_begin += std::chrono::microseconds(static_cast<std::int64_t>(p.duration / options_.speed_scaling * 1e6));
    } else {
      result = ur::TrajectoryResult::kFailure;
    }
    if (!ok) return;  // cancelled: the canceller answers
    if (result != ur::TrajectoryResult::kSuccess) break;
    first = false;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    qd_.setZero();
    trajectory_running_ = false;
  }
  sendResult(static_cast<std::int32_t>(result));
}

void SimUrRobot::sendResult(std::int32_t result) {
  std::uint8_t bytes[4];
  putInt32(bytes, result);
  std::lock_guard<std::mutex> lock(trajectory_write_);
  writeAll(trajectory_.fd(), bytes, sizeof bytes);
  std::lock_guard<std::mutex> state(mutex_);
  results_.push_back(result);
}

void SimUrRobot::rtdeLoop() {
  while (!stopping_) {
    Socket client = acceptTcp(rtde_listener_, 50);
    if (!client.valid()) continue;
    bool streaming = false;
    std::uint8_t recipe = 1;
    double period = 1.0 / 125.0;
    auto next = SteadyClock::now();
    while (!stopping_) {
      const int wait_ms = streaming ? 0 : 50;
      if (waitReadable(client.fd(), wait_ms)) {
        std::uint8_t header[3];
        if (readExact(client.fd(), header, 3, 500) != IoResult::kOk) break;
        const std::size_t size = static_cast<std::size_t>((header[0] << 8) | header[1]);
        if (size < 3) break;
        std::vector<std::uint8_t> payload(size - 3);
        if (!payload.empty() && readExact(client.fd(), payload.data(), payload.size(), 500) != IoResult::kOk) break;
        const std::uint8_t type = header[2];
        if (type == rtde::kRequestProtocolVersion && payload.size() == 2) {
          {
            std::lock_guard<std::mutex> lock(mutex_);
            rtde_version_ = (payload[0] << 8) | payload[1];
          }
          sendRtde(client.fd(), type, {1});
        } else if (type == rtde::kSetupOutputs && payload.size() >= 8) {
          const double frequency = getDouble(payload.data());
          const std::string names(payload.begin() + 8, payload.end());
          {
            std::lock_guard<std::mutex> lock(mutex_);
            rtde_outputs_ = names;
          }
          period = 1.0 / std::min(std::max(frequency, 1.0), options_.rtde_frequency_cap);
          std::vector<std::uint8_t> reply{recipe};
          const std::string types = names == rtde::kOutputs ? rtde::kOutputTypes : "NOT_FOUND";
          reply.insert(reply.end(), types.begin(), types.end());
          sendRtde(client.fd(), type, reply);
        } else if (type == rtde::kStart) {
          sendRtde(client.fd(), type, {1});
          streaming = true;
          next = SteadyClock::now();
        } else if (type == rtde::kPause) {
          sendRtde(client.fd(), type, {1});
          streaming = false;
        }
      }
      if (!streaming) continue;
      std::this_thread::sleep_until(next);
      next += std::chrono::microseconds(static_cast<std::int64_t>(period * 1e6));
      std::vector<std::uint8_t> data(rtde::kDataSize);
      data[0] = recipe;
      std::lock_guard<std::mutex> lock(mutex_);  // held while sending: stallRtde() sees the last package
      if (rtde_stalled_) continue;
      // The robot's timestamp is when q was measured: the last control step while moving, now at rest.
      const std::int64_t measured = trajectory_running_ && q_stamp_us_ != 0 ? q_stamp_us_ : steadyMicros();
      putDouble(data.data() + 1, (measured - epoch_us_) * 1e-6);
      const JointVector q = reportedLocked(measured);
      for (int j = 0; j < 6; ++j) {
        putDouble(data.data() + 9 + 8 * j, q[j]);
        putDouble(data.data() + 57 + 8 * j, qd_[j]);
      }
      if (!sendRtde(client.fd(), rtde::kDataPackage, data)) break;
      last_rtde_sent_us_ = measured;  // when the last state sent was measured
    }
  }
}

std::int64_t SimUrRobot::stoppedByPcAt() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return stopped_by_pc_us_;
}

std::int64_t SimUrRobot::stallRtde(bool stall) {
  std::lock_guard<std::mutex> lock(mutex_);
  rtde_stalled_ = stall;
  return last_rtde_sent_us_;
}

int SimUrRobot::trajectoryResultsSent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(results_.size());
}

bool SimUrRobot::programConnected() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return connected_;
}

std::string SimUrRobot::program() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return program_;
}

std::string SimUrRobot::programProblem() const {
  const std::string text = program();
  for (const char* marker : {"# HEADER_BEGIN", "# HEADER_END", "# NODE_CONTROL_LOOP_BEGINS", "# NODE_CONTROL_LOOP_ENDS"}) {
    if (text.find(marker) == std::string::npos) return std::string("missing marker ") + marker;
  }
  if (text.find("{{") != std::string::npos) return "a placeholder was not filled in";
  const std::string host = "\"" + options_.pc_host + "\", ";
  const std::pair<int, const char*> sockets[] = {{options_.trajectory_port, "trajectory_socket"},
                                                 {options_.script_command_port, "script_command_socket"},
                                                 {options_.reverse_port, "reverse_socket"}};
  for (const auto& [port, name] : sockets) {
    const std::string open = "socket_open(" + host + std::to_string(port) + ", \"" + name + "\")";
    if (text.find(open) == std::string::npos) return "no " + open;
  }
  if (text.find("MULT_jointstate = 1000000") == std::string::npos) return "MULT_jointstate is not 1000000";
  return "";
}

std::vector<SimUrRobot::ReceivedPoint> SimUrRobot::points() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return points_;
}

std::vector<SimUrRobot::ReverseRecord> SimUrRobot::commands() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return commands_;
}

std::vector<std::int64_t> SimUrRobot::cancelTimes() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return cancel_times_;
}

std::vector<std::int32_t> SimUrRobot::resultsSent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return results_;
}

int SimUrRobot::keepalives() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keepalives_;
}

double SimUrRobot::maxReverseGap() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return max_gap_;
}

bool SimUrRobot::halted() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return halted_;
}

std::string SimUrRobot::haltReason() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return halt_reason_;
}

JointVector SimUrRobot::q() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return q_;
}

int SimUrRobot::rtdeVersionAsked() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rtde_version_;
}

std::string SimUrRobot::rtdeOutputsAsked() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rtde_outputs_;
}

}  // namespace dash::dispatch::test
