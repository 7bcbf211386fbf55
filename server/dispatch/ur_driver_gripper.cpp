// UrDriver's gripper thread: connects to Robotiq's URCap socket and activates the gripper, runs the
// goal's grasp and release moves at their times and judges their object status, and checks the
// connection (GET STA) between moves, so that a dead gripper makes the arm not ready instead of
// failing the first grasp mid-motion.
#include <chrono>

#include "server/dispatch/ur_driver.h"

namespace dash::dispatch {

using SteadyClock = std::chrono::steady_clock;

namespace {

constexpr auto kGripperRetry = std::chrono::milliseconds(500);

std::chrono::microseconds seconds(double s) { return std::chrono::microseconds(static_cast<std::int64_t>(s * 1e6)); }

/// Why a finished move is not what the plan asked for; empty when it is.
std::string judgeMove(int position, int obj) {
  const bool closing = position > robotiq::kOpen;
  const std::string status = "(OBJ " + std::to_string(obj) + ": " + robotiq::objectStatusText(obj) + ")";
  if (closing) {
    if (obj == static_cast<int>(robotiq::ObjectStatus::kStoppedClosing)) return "";
    if (obj == static_cast<int>(robotiq::ObjectStatus::kAtPosition)) {
      return "missed grasp: the fingers closed on nothing " + status;
    }
    return "the grasp did not end on a part " + status;
  }
  if (obj == static_cast<int>(robotiq::ObjectStatus::kAtPosition)) return "";
  return "the release did not open the fingers fully " + status;
}

}  // namespace

bool UrDriver::gripperAnswers(std::string& error) {
  const std::optional<int> sta = gripper_.get("STA", error);
  if (!sta) return false;
  if (*sta != robotiq::kActive) {
    error = "STA " + std::to_string(*sta) + " (not activated)";
    return false;
  }
  return true;
}

bool UrDriver::connectGripper() {
  std::string error;
  bool ok =
      gripper_.connect(options_.gripper_host, options_.gripper_port, options_.gripper_timings.answer_timeout_ms, error);
  bool activated_before = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    activated_before = gripper_activated_;
    if (ok) gripper_error_ = "activating";
  }
  if (ok) {
    // The first time: Robotiq's activation (reset, then activate). After a lost connection a gripper
    // that is still active keeps its state (a reset would drop what it holds), as Robotiq's
    // activate() does.
    std::string ignored;
    const bool still_active = activated_before && gripperAnswers(ignored);
    ok = still_active || gripper_.activate([this] { return stopping_.load(); }, error);
    if (!ok) gripper_.close();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  gripper_ready_ = ok;
  gripper_error_ = ok ? "" : error;
  if (ok && !activated_before) gripper_closed_ = false;
  gripper_activated_ = gripper_activated_ || ok;
  next_gripper_poll_ = SteadyClock::now() + seconds(options_.gripper_poll);
  cv_.notify_all();
  return ok;
}

void UrDriver::runGripperMove(int position, std::uint64_t goal_seq) {
  const RobotiqGripper::MoveResult r =
      gripper_.move(position, options_.gripper_speed, options_.gripper_force,
                    [this, goal_seq] { return stopping_.load() || goal_seq_.load() != goal_seq; });
  std::lock_guard<std::mutex> lock(mutex_);
  gripper_moving_ = false;
  next_gripper_poll_ = SteadyClock::now() + seconds(options_.gripper_poll);
  const bool same_goal = goal_seq_.load() == goal_seq && phase_ != Phase::kIdle;
  if (!r.ok) {
    if (!gripper_.connected()) {
      gripper_ready_ = false;
      gripper_error_ = r.error;
    }
    if (same_goal) failLocked(ArmStatus::kFailed, ResultCode::kFault, "gripper: " + r.error);
  } else {
    gripper_closed_ = position > robotiq::kOpen;
    const std::string problem = judgeMove(position, r.obj);
    if (!problem.empty() && same_goal) failLocked(ArmStatus::kFailed, ResultCode::kFault, "gripper: " + problem);
  }
  cv_.notify_all();
}

void UrDriver::pollGripper() {
  std::string error;
  const bool ok = gripperAnswers(error);
  std::lock_guard<std::mutex> lock(mutex_);
  next_gripper_poll_ = SteadyClock::now() + seconds(options_.gripper_poll);
  if (ok) return;
  gripper_ready_ = false;
  gripper_error_ = error;
  if (gripper_.connected()) gripper_.close();  // start over: reconnect and check activation
  if (phase_ != Phase::kIdle && phase_ != Phase::kCancelling) {
    failLocked(ArmStatus::kFailed, ResultCode::kFault, "the gripper stopped answering: " + error);
  }
  cv_.notify_all();
}

void UrDriver::gripperLoop() {
  while (!stopping_) {
    if (!gripper_.connected()) {
      if (!connectGripper()) {
        std::unique_lock<std::mutex> lock(mutex_);
        cv_.wait_for(lock, kGripperRetry, [&] { return stopping_.load(); });
      }
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    auto due = [&] {
      return gripper_next_ < gripper_plan_.size() && gripper_plan_[gripper_next_].first <= SteadyClock::now();
    };
    auto wake = next_gripper_poll_;
    if (gripper_next_ < gripper_plan_.size()) wake = std::min(wake, gripper_plan_[gripper_next_].first);
    cv_.wait_until(lock, wake, [&] { return stopping_.load() || due() || SteadyClock::now() >= next_gripper_poll_; });
    if (stopping_) break;
    if (due()) {
      const int position = gripper_plan_[gripper_next_].second;
      ++gripper_next_;
      gripper_moving_ = true;
      const std::uint64_t seq = goal_seq_.load();
      lock.unlock();
      runGripperMove(position, seq);
    } else if (SteadyClock::now() >= next_gripper_poll_) {
      lock.unlock();
      pollGripper();
    }
  }
}

}  // namespace dash::dispatch
