#include "server/dispatch/ur_driver.h"

#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <limits>

#include "engine/core/check.h"

namespace dash::dispatch {

using SteadyClock = std::chrono::steady_clock;

namespace {

std::chrono::microseconds seconds(double s) { return std::chrono::microseconds(static_cast<std::int64_t>(s * 1e6)); }

}  // namespace

UrDriver::UrDriver(const RobotModel& model, UrDriverOptions options)
    : model_name_(model.name),
      joint_names_(model.joint_names),
      velocity_max_(model.limits.velocity_max),
      options_(std::move(options)),
      gripper_(options_.gripper_timings) {
  DASH_THROW_UNLESS(model.dof() == 6, "--driver ur needs a 6-joint arm model, " + model.name + " has " +
                                          std::to_string(model.dof()) + " joints");
  DASH_THROW_UNLESS(!options_.robot_ip.empty(), "--driver ur needs --robot-ip");
  DASH_THROW_UNLESS(options_.keepalive_ms > 0 && options_.keepalive_ms < options_.read_timeout_ms,
                    "the keep-alive period must be shorter than the read timeout");
  DASH_THROW_UNLESS(options_.rtde_frequency > 0.0 && options_.state_stale_after >= 0.0 && options_.gripper_poll > 0.0,
                    "the RTDE frequency, the staleness bound and the gripper poll period must be positive");
  reverse_.name = "reverse";
  script_.name = "script sender";
  trajectory_.name = "trajectory";
  command_.name = "script command";
  reverse_.listener = listenTcp(options_.listen_host, options_.reverse_port);
  script_.listener = listenTcp(options_.listen_host, options_.script_port);
  trajectory_.listener = listenTcp(options_.listen_host, options_.trajectory_port);
  command_.listener = listenTcp(options_.listen_host, options_.script_command_port);
  ports_ = {boundPort(reverse_.listener), boundPort(script_.listener), boundPort(trajectory_.listener),
            boundPort(command_.listener)};
  rtde_ = std::make_unique<RtdeClient>(RtdeOptions{options_.robot_ip, options_.rtde_port, options_.rtde_frequency});
  if (options_.gripper_host.empty()) options_.gripper_host = options_.robot_ip;
  io_thread_ = std::thread([this] { ioLoop(); });
  control_thread_ = std::thread([this] { controlLoop(); });
  if (options_.gripper) gripper_thread_ = std::thread([this] { gripperLoop(); });
}

UrDriver::~UrDriver() { shutdown(); }

void UrDriver::shutdown() {
  if (stopping_.exchange(true)) return;
  ++goal_seq_;
  cv_.notify_all();
  if (control_thread_.joinable()) control_thread_.join();  // no keep-alive after MODE_STOPPED
  if (gripper_thread_.joinable()) gripper_thread_.join();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (phase_ == Phase::kSent || phase_ == Phase::kCancelling) {
      sendReverse(ur::forwardMessage(options_.read_timeout_ms, ur::TrajectoryAction::kCancel));
    }
    // As UR's client library does before closing: the program leaves its loop and stops the arm.
    sendReverse(ur::stoppedMessage(options_.read_timeout_ms));
  }
  if (io_thread_.joinable()) io_thread_.join();
  if (rtde_) rtde_->stop();
  gripper_.close();
  for (Endpoint* e : {&reverse_, &script_, &trajectory_, &command_}) {
    std::lock_guard<std::mutex> lock(e->write_mutex);
    e->client.reset();
    e->listener.reset();
  }
}

// ---------------------------------------------------------------- sockets

bool UrDriver::connectedLocked(const Endpoint& endpoint) const { return endpoint.client.valid(); }

bool UrDriver::robotConnected() const {
  std::lock_guard<std::mutex> a(reverse_.write_mutex);
  std::lock_guard<std::mutex> b(trajectory_.write_mutex);
  return connectedLocked(reverse_) && connectedLocked(trajectory_);
}

bool UrDriver::sendReverse(const ur::ReverseMessage& message) {
  const auto bytes = ur::encode(message);
  std::lock_guard<std::mutex> lock(reverse_.write_mutex);
  return reverse_.client.valid() && writeAll(reverse_.client.fd(), bytes.data(), bytes.size());
}

bool UrDriver::sendPoints(const std::vector<ur::PointMessage>& points) {
  std::lock_guard<std::mutex> lock(trajectory_.write_mutex);
  if (!trajectory_.client.valid()) return false;
  for (const ur::PointMessage& p : points) {
    const auto bytes = ur::encode(p);
    if (!writeAll(trajectory_.client.fd(), bytes.data(), bytes.size())) return false;
  }
  return true;
}

void UrDriver::dropClient(Endpoint& endpoint, const std::string& why) {
  {
    std::lock_guard<std::mutex> lock(endpoint.write_mutex);
    endpoint.client.reset();
    endpoint.inbox.clear();
  }
  if (&endpoint != &reverse_ && &endpoint != &trajectory_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (phase_ != Phase::kIdle) {
    failLocked(ArmStatus::kFailed, ResultCode::kFault, "the robot program disconnected (" + endpoint.name + " socket: " + why + ")");
  }
}

void UrDriver::ioLoop() {
  Endpoint* endpoints[] = {&reverse_, &script_, &trajectory_, &command_};
  while (!stopping_) {
    pollfd fds[8];
    Endpoint* owner[8];
    bool is_listener[8];
    nfds_t n = 0;
    for (Endpoint* e : endpoints) {
      fds[n] = {e->listener.fd(), POLLIN, 0};
      owner[n] = e;
      is_listener[n++] = true;
      if (e->client.valid()) {  // only this thread replaces clients
        fds[n] = {e->client.fd(), POLLIN, 0};
        owner[n] = e;
        is_listener[n++] = false;
      }
    }
    const int ready = ::poll(fds, n, 20);
    if (ready <= 0) continue;
    for (nfds_t i = 0; i < n; ++i) {
      if (fds[i].revents == 0) continue;
      Endpoint& e = *owner[i];
      if (is_listener[i]) {
        Socket s = acceptTcp(e.listener, 0);
        if (!s.valid()) continue;
        std::lock_guard<std::mutex> lock(e.write_mutex);
        if (!e.client.valid()) {
          e.client = std::move(s);
          e.inbox.clear();
        }  // else: each server takes one client; the new connection is closed
      } else {
        handleReadable(e);
      }
    }
  }
}

void UrDriver::handleReadable(Endpoint& e) {
  char buffer[1024];
  const ssize_t k = ::recv(e.client.fd(), buffer, sizeof buffer, MSG_DONTWAIT);
  if (k < 0 && (errno == EAGAIN || errno == EINTR)) return;
  if (k <= 0) {
    dropClient(e, k == 0 ? "closed by the robot" : "read error");
    return;
  }
  e.inbox.append(buffer, static_cast<std::size_t>(k));
  if (&e == &script_) {
    for (std::size_t nl = e.inbox.find('\n'); nl != std::string::npos; nl = e.inbox.find('\n')) {
      const std::string line = e.inbox.substr(0, nl + 1);
      e.inbox.erase(0, nl + 1);
      if (line != ur::kProgramRequest) continue;
      std::string host = options_.host_ip;
      if (host.empty()) host = rtde_->localAddress();
      if (host.empty()) host = options_.listen_host == "0.0.0.0" ? "127.0.0.1" : options_.listen_host;
      const std::string text = ur::program({host, ports_.reverse, ports_.trajectory, ports_.script_command});
      std::lock_guard<std::mutex> lock(e.write_mutex);
      if (e.client.valid()) writeAll(e.client.fd(), text.data(), text.size());
    }
  } else if (&e == &trajectory_) {
    while (e.inbox.size() >= 4) {
      const std::int32_t result = getInt32(reinterpret_cast<const std::uint8_t*>(e.inbox.data()));
      e.inbox.erase(0, 4);
      handleResult(result);
    }
  } else {
    e.inbox.clear();  // the robot sends nothing else we use
  }
}

// ---------------------------------------------------------------- goals

void UrDriver::failLocked(ArmStatus status, ResultCode code, const std::string& message) {
  if (phase_ == Phase::kSent) sendReverse(ur::forwardMessage(options_.read_timeout_ms, ur::TrajectoryAction::kCancel));
  progress_ = {status, code, message};
  phase_ = Phase::kIdle;
  gripper_next_ = gripper_plan_.size();
  ++goal_seq_;
  cv_.notify_all();
}

double UrDriver::staleBound() const {
  return options_.state_stale_after > 0.0 ? options_.state_stale_after
                                          : kStalePeriods / options_.rtde_frequency + kStaleMargin;
}

void UrDriver::handleResult(std::int32_t result) {
  std::lock_guard<std::mutex> lock(mutex_);
  const ResultCode code = ur::mapTrajectoryResult(result);
  if (phase_ == Phase::kCancelling) {
    progress_ = {ArmStatus::kAborted, ResultCode::kCancelled, abort_reason_};
    phase_ = Phase::kIdle;
    ++goal_seq_;
  } else if (phase_ == Phase::kSent) {
    if (code == ResultCode::kSuccessful) {
      phase_ = Phase::kGoalCheck;
      auto until = SteadyClock::now();
      if (!gripper_plan_.empty()) until = std::max(until, gripper_plan_.back().first);
      deadline_ = until + seconds(limits_.goal_time_tolerance);
    } else if (code == ResultCode::kCancelled) {
      progress_ = {ArmStatus::kFailed, code, "the robot cancelled the trajectory"};
      phase_ = Phase::kIdle;
    ++goal_seq_;
    } else {
      progress_ = {ArmStatus::kFailed, code,
                   code == ResultCode::kPathToleranceViolated ? "the robot reported a trajectory failure (result 2)"
                                                               : "unknown trajectory result " + std::to_string(result)};
      phase_ = Phase::kIdle;
    ++goal_seq_;
    }
  }  // else: a late answer (a CANCEL after the end); nothing is running
  cv_.notify_all();
}

bool UrDriver::ready(std::string& detail) const {
  if (!robotConnected()) {
    detail = "waiting for the robot program (External Control) to connect";
    return false;
  }
  const DriverState s = state();
  if (!s.valid) {
    detail = "waiting for RTDE joint states from " + options_.robot_ip + ":" + std::to_string(options_.rtde_port);
    return false;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (options_.gripper && !gripper_ready_) {
    detail = "waiting for the gripper" + (gripper_error_.empty() ? "" : ": " + gripper_error_);
    return false;
  }
  if (phase_ != Phase::kIdle) {
    detail = "running a goal";
    return false;
  }
  detail = "robot program connected";
  return true;
}

DriverState UrDriver::state() const {
  const RtdeClient::State s = rtde_->state();
  const bool fresh = s.connected && s.measured_us != 0 &&
                     (steadyMicros() - s.measured_us) <= static_cast<std::int64_t>(staleBound() * 1e6);
  return {fresh, s.q, s.qd, s.measured_us};
}

ResultCode UrDriver::load(const ArmTrajectory& trajectory, const GoalLimits& limits, std::string& message) {
  std::string detail;
  const bool is_ready = ready(detail);
  const DriverState s = state();
  std::unique_lock<std::mutex> lock(mutex_);
  auto refuse = [&](ResultCode code, const std::string& why) {
    message = why;
    progress_ = {ArmStatus::kFailed, code, why};
    return code;
  };
  if (!is_ready) return refuse(ResultCode::kInvalidGoal, "not ready: " + detail);
  ResultCode code = checkGoal(trajectory, joint_names_, s, velocity_max_, limits, message);
  if (code != ResultCode::kSuccessful) return refuse(code, message);
  if (!trajectory.gripper.empty() && !options_.gripper) {
    return refuse(ResultCode::kInvalidGoal, "the goal has grasp/release commands but no gripper is configured (--gripper robotiq)");
  }
  if (options_.gripper) {  // a dead gripper connection must not wait for the first grasp to show
    std::string why;
    lock.unlock();
    const bool answers = gripperAnswers(why);
    lock.lock();
    if (!answers) {
      gripper_ready_ = false;  // the gripper thread reconnects (and checks the activation)
      gripper_error_ = why;
      return refuse(ResultCode::kInvalidGoal, "the gripper does not answer: " + why);
    }
    if (phase_ != Phase::kIdle) return refuse(ResultCode::kInvalidGoal, "busy with another goal");
  }
  std::vector<ur::PointMessage> points;
  const std::string problem = ur::buildPointMessages(trajectory, s.q, limits.start_tolerance, options_.point_type, points);
  if (!problem.empty()) return refuse(ResultCode::kInvalidGoal, problem);
  goal_ = trajectory;
  limits_ = limits;
  points_ = std::move(points);
  gripper_plan_.clear();
  gripper_next_ = 0;
  ++goal_seq_;
  phase_ = Phase::kArmed;
  progress_ = {ArmStatus::kArmed, ResultCode::kSuccessful, ""};
  message.clear();
  return ResultCode::kSuccessful;
}

void UrDriver::start(SteadyClock::time_point at) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (phase_ != Phase::kArmed) return;
  start_at_ = at;
  phase_ = Phase::kWaitingStart;
  gripper_plan_.clear();
  for (const GripperCommand& g : goal_.gripper) {
    gripper_plan_.emplace_back(at + seconds(g.t), g.action == GripperCommand::Action::kGrasp ? robotiq::kClosed : robotiq::kOpen);
  }
  gripper_next_ = 0;
  cv_.notify_all();
}

void UrDriver::abort(const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  gripper_next_ = gripper_plan_.size();
  ++goal_seq_;
  switch (phase_) {
    case Phase::kArmed:
    case Phase::kWaitingStart:
    case Phase::kGoalCheck:
      progress_ = {ArmStatus::kAborted, ResultCode::kCancelled, reason};
      phase_ = Phase::kIdle;
      break;
    case Phase::kSent:
      abort_reason_ = reason;
      sendReverse(ur::forwardMessage(options_.read_timeout_ms, ur::TrajectoryAction::kCancel));
      phase_ = Phase::kCancelling;
      deadline_ = SteadyClock::now() + seconds(options_.cancel_timeout);
      break;
    case Phase::kCancelling:
    case Phase::kIdle:
      break;
  }
  cv_.notify_all();
}

DriverProgress UrDriver::progress() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return progress_;
}

std::string UrDriver::gripperState() const {
  if (!options_.gripper) return "";
  std::lock_guard<std::mutex> lock(mutex_);
  return gripper_closed_ ? "closed" : "open";
}

void UrDriver::controlLoop() {
  const auto period = std::chrono::milliseconds(options_.keepalive_ms);
  auto next_keepalive = SteadyClock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    auto wake = next_keepalive;
    if (phase_ == Phase::kWaitingStart) wake = std::min(wake, start_at_);
    cv_.wait_until(lock, wake, [&] { return stopping_.load() || (phase_ == Phase::kWaitingStart && SteadyClock::now() >= start_at_); });
    if (stopping_) break;
    const auto now = SteadyClock::now();
    if (phase_ == Phase::kWaitingStart && now >= start_at_) {
      if (points_.empty()) {  // nothing to move: only the gripper, if anything
        phase_ = Phase::kGoalCheck;
        auto until = now;
        if (!gripper_plan_.empty()) until = std::max(until, gripper_plan_.back().first);
        deadline_ = until + seconds(limits_.goal_time_tolerance);
        progress_.status = ArmStatus::kExecuting;
      } else {
        const auto count = static_cast<std::int32_t>(points_.size());
        const bool sent = sendReverse(ur::forwardMessage(options_.read_timeout_ms, ur::TrajectoryAction::kStart, count)) &&
                          sendPoints(points_);
        if (sent) {
          phase_ = Phase::kSent;
          progress_.status = ArmStatus::kExecuting;
        } else {
          failLocked(ArmStatus::kFailed, ResultCode::kFault, "could not send the trajectory: the robot program is not connected");
        }
      }
      next_keepalive = now + period;
      cv_.notify_all();
      continue;
    }
    if (now >= next_keepalive) {
      const bool forward = phase_ == Phase::kSent || phase_ == Phase::kCancelling;
      sendReverse(forward ? ur::forwardMessage(options_.read_timeout_ms, ur::TrajectoryAction::kNoop)
                          : ur::idleMessage(options_.read_timeout_ms));
      next_keepalive = now + period;
    }
    checkGoalLocked(now);
  }
}

void UrDriver::checkGoalLocked(SteadyClock::time_point now) {
  const bool in_progress = phase_ == Phase::kArmed || phase_ == Phase::kWaitingStart || phase_ == Phase::kSent ||
                           phase_ == Phase::kGoalCheck;
  if (in_progress) {
    // Without fresh joint state nobody can tell where the arm is: stop it (the server then aborts
    // every arm when this one reports the fault).
    const RtdeClient::State rs = rtde_->state();
    const double age = rs.measured_us == 0 ? std::numeric_limits<double>::infinity()
                                           : (steadyMicros() - rs.measured_us) * 1e-6;
    if (!rs.connected || age > staleBound()) {
      char text[200];
      std::snprintf(text, sizeof text, "no joint state from RTDE for %.0f ms (staleness bound %.0f ms): arm stopped",
                    std::min(age, 1e9) * 1e3, staleBound() * 1e3);
      failLocked(ArmStatus::kFailed, ResultCode::kFault, text);
      return;
    }
  }
  if (phase_ == Phase::kCancelling && now > deadline_) {
    // Unconfirmed: end the program (it stops the arm on MODE_STOPPED); the operator restarts it.
    sendReverse(ur::stoppedMessage(options_.read_timeout_ms));
    progress_ = {ArmStatus::kAborted, ResultCode::kFault,
                 "the robot did not confirm the cancel (MODE_STOPPED sent): " + abort_reason_};
    phase_ = Phase::kIdle;
    ++goal_seq_;
  } else if (phase_ == Phase::kGoalCheck) {
    const DriverState s = state();
    const bool gripper_done = gripper_next_ >= gripper_plan_.size() && !gripper_moving_;
    const JointVector& goal = goal_.points.back().positions;
    const ToleranceCheck off = s.valid ? checkTolerance(s.q, goal, limits_.goalTolerance(goal.size())) : ToleranceCheck{true};
    if (!off.violated && gripper_done) {
      progress_ = {ArmStatus::kSucceeded, ResultCode::kSuccessful, ""};
      phase_ = Phase::kIdle;
      ++goal_seq_;
    } else if (now > deadline_) {
      const double t = std::chrono::duration<double>(now - start_at_).count();
      progress_ = {ArmStatus::kFailed, ResultCode::kGoalToleranceViolated,
                   gripper_done ? describeViolation(off, joint_names_, "goal", t) : "gripper commands still pending"};
      phase_ = Phase::kIdle;
      ++goal_seq_;
    }
  }
}

}  // namespace dash::dispatch
