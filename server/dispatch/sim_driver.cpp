#include "server/dispatch/sim_driver.h"

#include <algorithm>

namespace dash::dispatch {

using SteadyClock = std::chrono::steady_clock;

SimDriver::SimDriver(const RobotModel& model, SimDriverOptions options)
    : model_name_(model.name),
      joint_names_(model.joint_names),
      velocity_max_(model.limits.velocity_max),
      options_(std::move(options)),
      rng_(options_.seed) {
  q_ = options_.initial.size() == model.dof() ? options_.initial : JointVector::Zero(model.dof());
  qd_ = JointVector::Zero(model.dof());
  thread_ = std::thread([this] { loop(); });
}

SimDriver::~SimDriver() { shutdown(); }

void SimDriver::shutdown() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

bool SimDriver::ready(std::string& detail) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const bool busy = progress_.status == ArmStatus::kArmed || progress_.status == ArmStatus::kExecuting;
  detail = busy ? "running a goal" : "simulated arm";
  return !busy;
}

DriverState SimDriver::state() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {true, q_, qd_, stamp_us_};
}

ResultCode SimDriver::load(const ArmTrajectory& trajectory, const GoalLimits& limits, std::string& message) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (progress_.status == ArmStatus::kArmed || progress_.status == ArmStatus::kExecuting) {
    message = "busy with another goal";
    return ResultCode::kInvalidGoal;
  }
  ResultCode code = ResultCode::kSuccessful;
  if (options_.refuse) {
    code = ResultCode::kInvalidGoal;
    message = "goal refused (--sim-refuse)";
  } else {
    code = checkGoal(trajectory, joint_names_, {true, q_, qd_}, velocity_max_, limits, message);
  }
  if (code != ResultCode::kSuccessful) {
    progress_ = {ArmStatus::kFailed, code, message};
    return code;
  }
  goal_ = trajectory;
  limits_ = limits;
  started_ = false;
  next_gripper_ = 0;
  tau_ = 0.0;
  paused_until_ = {};
  gripper_done_at_.reset();
  gripper_log_.clear();
  progress_ = {ArmStatus::kArmed, ResultCode::kSuccessful, ""};
  return code;
}

void SimDriver::start(SteadyClock::time_point at) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (progress_.status != ArmStatus::kArmed) return;
  start_time_ = at;
  started_ = true;
}

void SimDriver::abort(const std::string& reason) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (progress_.status == ArmStatus::kArmed || progress_.status == ArmStatus::kExecuting) {
    progress_ = {ArmStatus::kAborted, ResultCode::kCancelled, reason};
    qd_.setZero();
    started_ = false;
    gripper_done_at_.reset();
    last_abort_ = SteadyClock::now();
  }
}

DriverProgress SimDriver::progress() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return progress_;
}

std::string SimDriver::gripperState() const {
  if (!options_.gripper) return "";
  std::lock_guard<std::mutex> lock(mutex_);
  return gripper_closed_ ? "closed" : "open";
}

std::optional<SteadyClock::time_point> SimDriver::lastAbortTime() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_abort_;
}

std::vector<std::pair<double, GripperCommand::Action>> SimDriver::gripperLog() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return gripper_log_;
}

void SimDriver::loop() {
  const auto step = std::chrono::microseconds(static_cast<std::int64_t>(options_.step * 1e6));
  auto last = SteadyClock::now();
  std::unique_lock<std::mutex> lock(mutex_);
  while (!stopping_) {
    cv_.wait_for(lock, step, [&] { return stopping_; });
    const auto now = SteadyClock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    stepLocked(now, dt);
    stamp_us_ = std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count();
  }
}

void SimDriver::stepLocked(SteadyClock::time_point now, double dt) {
  const bool running = started_ && (progress_.status == ArmStatus::kArmed || progress_.status == ArmStatus::kExecuting);
  if (!running || now < start_time_ || dt <= 0.0) {
    qd_.setZero();
    return;
  }
  progress_.status = ArmStatus::kExecuting;
  const double elapsed = std::chrono::duration<double>(now - start_time_).count();
  if (options_.stop_at && elapsed >= *options_.stop_at) {  // frozen: a silent stop
    qd_.setZero();
    return;
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  if (now >= paused_until_) {
    if (options_.pause_rate > 0.0 && tau_ < goal_.duration() && unit(rng_) < options_.pause_rate * dt) {
      paused_until_ = now + std::chrono::microseconds(static_cast<std::int64_t>(unit(rng_) * options_.pause_max * 1e6));
    } else {
      tau_ += std::min(dt, elapsed) * options_.speed;
    }
  }
  const JointVector target = goal_.positionAt(tau_);
  const JointVector before = q_;
  for (Eigen::Index j = 0; j < q_.size(); ++j) {
    const double max_step = velocity_max_[j] * dt;
    q_[j] += std::clamp(target[j] - q_[j], -max_step, max_step);
  }
  qd_ = (q_ - before) / dt;
  stepGripperLocked(now, elapsed);
  const JointVector& goal = goal_.points.back().positions;
  const ToleranceCheck off = checkTolerance(q_, goal, limits_.goalTolerance(q_.size()));
  const bool gripper_busy = gripper_done_at_.has_value();
  if (tau_ >= goal_.endTime() && !off.violated && !gripper_busy) {
    progress_ = {ArmStatus::kSucceeded, ResultCode::kSuccessful, ""};
    qd_.setZero();
  } else if (tau_ >= goal_.endTime() + limits_.goal_time_tolerance) {
    progress_ = {ArmStatus::kFailed, ResultCode::kGoalToleranceViolated,
                 (gripper_busy ? std::string("the gripper is still moving") : describeViolation(off, joint_names_, "goal", tau_)) +
                     ", goal time tolerance " + std::to_string(limits_.goal_time_tolerance) + " s"};
    qd_.setZero();
  }
}

void SimDriver::stepGripperLocked(SteadyClock::time_point now, double elapsed) {
  if (gripper_done_at_ && now >= *gripper_done_at_) {
    gripper_closed_ = gripper_target_closed_;
    gripper_done_at_.reset();
  }
  while (!gripper_done_at_ && next_gripper_ < goal_.gripper.size() && goal_.gripper[next_gripper_].t <= tau_) {
    const GripperCommand& g = goal_.gripper[next_gripper_++];
    gripper_target_closed_ = g.action == GripperCommand::Action::kGrasp;
    gripper_log_.emplace_back(elapsed, g.action);
    std::uniform_real_distribution<double> jitter(-options_.gripper_jitter, options_.gripper_jitter);
    const double takes = std::max(0.0, options_.gripper_time + (options_.gripper_jitter > 0.0 ? jitter(rng_) : 0.0));
    if (takes <= 0.0) {
      gripper_closed_ = gripper_target_closed_;
    } else {
      gripper_done_at_ = now + std::chrono::microseconds(static_cast<std::int64_t>(takes * 1e6));
    }
  }
}

}  // namespace dash::dispatch
