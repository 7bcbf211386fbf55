#include "server/dispatch/dispatch_service.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "engine/core/check.h"

namespace dash::dispatch {

namespace {

constexpr int kAccepted = 202;
constexpr int kConflict = 409;
constexpr int kUnavailable = 503;
constexpr int kGatewayTimeout = 504;
constexpr double kDeadlineSlack = 0.25;  ///< s on top of goal_time_tolerance before giving up on an arm

std::int64_t micros(double seconds) { return static_cast<std::int64_t>(std::llround(seconds * 1e6)); }

std::string fmt(double v, int decimals = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string resultText(ResultCode code, const std::string& message) {
  return std::string(resultCodeName(code)) + (message.empty() ? "" : ": " + message);
}

/// Wall-clock milliseconds, for dispatch ids that stay unique across server restarts (and a random
/// tag per service across servers).
long long wallMillis() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

const char* dispatchStateName(DispatchState state) {
  switch (state) {
    case DispatchState::kArming: return "arming";
    case DispatchState::kRunning: return "running";
    case DispatchState::kSucceeded: return "succeeded";
    case DispatchState::kFailed: return "failed";
    case DispatchState::kAborted: return "aborted";
    case DispatchState::kRefused: return "refused";
  }
  return "unknown";
}

DispatchService::DispatchService(DispatchConfig config) : config_(std::move(config)) {
  if (!config_.library) config_.library = RobotLibrary::loadDefault();
  std::random_device device;
  char tag[16];
  std::snprintf(tag, sizeof tag, "%08x", static_cast<unsigned>(device()));
  id_tag_ = tag;
  monitor_ = std::thread([this] { monitorLoop(); });
}

DispatchService::~DispatchService() { shutdown(); }

std::int64_t DispatchService::now() const { return steadyMicros(); }

void DispatchService::shutdown() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!stopping_) {
      stopping_ = true;
      for (auto& [robot, entry] : controllers_) {
        if (entry.stream) entry.stream->close();
      }
    }
  }
  cv_.notify_all();
  if (monitor_.joinable()) monitor_.join();
}

void DispatchService::addListener(std::shared_ptr<DispatchListener> listener) {
  std::lock_guard<std::mutex> lock(mutex_);
  listeners_.push_back(std::move(listener));
}

void DispatchService::removeListener(const std::shared_ptr<DispatchListener>& listener) {
  std::lock_guard<std::mutex> lock(mutex_);
  listeners_.erase(std::remove(listeners_.begin(), listeners_.end(), listener), listeners_.end());
}

void DispatchService::noteLocked(std::function<void(DispatchListener&)> call) {
  if (listeners_.empty()) return;
  auto listeners = listeners_;
  pending_notes_.push_back([listeners, call = std::move(call)] {
    for (const auto& l : listeners) call(*l);
  });
}

void DispatchService::drainNotes() {
  std::lock_guard<std::mutex> order(notes_mutex_);
  for (;;) {
    std::function<void()> next;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (pending_notes_.empty()) return;
      next = std::move(pending_notes_.front());
      pending_notes_.pop_front();
    }
    next();
  }
}

// ---------------------------------------------------------------- agents

DispatchService::StreamHandle DispatchService::openStream(const std::string& robot) {
  StreamHandle handle;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    handle.stream = std::make_shared<CommandStream>();
    if (stopping_) {
      handle.stream->close();
      return handle;
    }
    ControllerEntry& entry = controllers_[robot];
    const bool seen = !entry.info.robot.empty();
    if (entry.stream) entry.stream->close();
    if (entry.info.connected) {
      const ControllerInfo old = entry.info;
      noteLocked([old](DispatchListener& l) { l.onControllerDisconnected(old, "replaced by a new connection"); });
      const int arm = armIndexLocked(robot);
      if (arm >= 0 && isActive(run_->status.state) && !run_->status.arms[static_cast<std::size_t>(arm)].done) {
        auto& a = run_->status.arms[static_cast<std::size_t>(arm)];
        a.done = true;
        a.result = ResultCode::kFault;
        a.message = "the controller reconnected: its previous connection was lost";
        abortLocked(robot + ": the controller's connection was lost (it reconnected)", DispatchState::kAborted);
      }
    }
    entry.info.robot = robot;
    entry.info.session = "s" + std::to_string(next_session_++);
    entry.info.connected = true;
    entry.info.ready = false;
    entry.info.detail = "connected";
    entry.info.connected_since_us = now();
    entry.info.last_report_us = 0;
    if (seen) ++entry.info.reconnects;
    entry.stream = handle.stream;
    handle.session = entry.info.session;
    handle.stream->push(formatSse("hello", helloToJson({entry.info.session, now(), robot, steadyClockId()})));
    const ControllerInfo info = entry.info;
    noteLocked([info](DispatchListener& l) { l.onControllerConnected(info); });
  }
  drainNotes();
  return handle;
}

void DispatchService::closeStream(const std::string& robot, const std::string& session, const std::string& reason) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = controllers_.find(robot);
    if (it == controllers_.end() || it->second.info.session != session || !it->second.info.connected) return;
    ControllerEntry& entry = it->second;
    entry.info.connected = false;
    entry.info.ready = false;
    entry.info.detail = "disconnected: " + reason;
    if (entry.stream) entry.stream->close();
    entry.stream.reset();
    const ControllerInfo info = entry.info;
    noteLocked([info, reason](DispatchListener& l) { l.onControllerDisconnected(info, reason); });
    const int arm = armIndexLocked(robot);
    if (arm >= 0 && isActive(run_->status.state) && !run_->status.arms[static_cast<std::size_t>(arm)].done) {
      auto& a = run_->status.arms[static_cast<std::size_t>(arm)];
      a.done = true;
      a.result = ResultCode::kFault;
      a.message = "the controller disconnected (" + reason + ")";
      abortLocked(robot + ": the controller disconnected (" + reason + ")", DispatchState::kAborted);
    }
  }
  cv_.notify_all();
  drainNotes();
}

ReportResult DispatchService::report(const std::string& robot, const AgentReport& r) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto it = controllers_.find(robot);
    if (it == controllers_.end() || !it->second.info.connected || it->second.info.session != r.session) {
      return ReportResult::kStaleSession;
    }
    ControllerEntry& entry = it->second;
    ControllerInfo& info = entry.info;
    const bool changed = info.status != r.status || info.ready != r.ready || info.result != r.result ||
                         info.dispatch_id != r.dispatch_id || info.detail != r.detail || info.gripper != r.gripper ||
                         info.driver != r.driver || info.message != r.message;
    info.driver = r.driver;
    info.model = r.model;
    info.joint_names = r.joint_names;
    info.ready = r.ready;
    info.detail = r.detail;
    info.status = r.status;
    info.dispatch_id = r.dispatch_id;
    info.result = r.result;
    info.message = r.message;
    info.gripper = r.gripper;
    const std::int64_t t = now();
    info.last_report_us = t;
    if (!r.samples.empty()) info.last_sample = r.samples.back();
    const bool due = config_.state_event_hz > 0 &&
                     t - entry.last_state_event_us >= micros(1.0 / config_.state_event_hz);
    if (changed || due) {
      entry.last_state_event_us = t;
      const ControllerInfo copy = info;
      noteLocked([copy](DispatchListener& l) { l.onControllerState(copy); });
    }
    const int arm = armIndexLocked(robot);
    if (arm >= 0 && !run_->status.final) {
      processSamplesLocked(static_cast<std::size_t>(arm), r.samples);
      if (r.dispatch_id == run_->status.id) processStatusLocked(static_cast<std::size_t>(arm), r);
    }
  }
  cv_.notify_all();
  drainNotes();
  return ReportResult::kOk;
}

std::vector<ControllerInfo> DispatchService::controllers() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<ControllerInfo> out;
  for (const auto& [robot, entry] : controllers_) out.push_back(entry.info);
  return out;
}

// ---------------------------------------------------------------- dispatch

int DispatchService::armIndexLocked(const std::string& robot) const {
  if (!run_) return -1;
  for (std::size_t i = 0; i < run_->status.arms.size(); ++i) {
    if (run_->status.arms[i].robot == robot) return static_cast<int>(i);
  }
  return -1;
}

bool DispatchService::allArmsDoneLocked() const {
  return std::all_of(run_->status.arms.begin(), run_->status.arms.end(),
                     [](const ArmDispatchStatus& a) { return a.done; });
}

int DispatchService::pushToAllLocked(const std::string& event) {
  int n = 0;
  for (auto& [robot, entry] : controllers_) {
    if (entry.info.connected && entry.stream) {
      entry.stream->push(event);
      ++n;
    }
  }
  return n;
}

void DispatchService::processSamplesLocked(std::size_t i, const std::vector<JointSample>& samples) {
  Run& run = *run_;
  ArmDispatchStatus& arm = run.status.arms[i];
  const ArmTrajectory& trajectory = run.trajectories[i];
  const Eigen::Index dof = trajectory.points.front().positions.size();
  for (const JointSample& s : samples) {
    if (s.q.size() != dof) continue;
    run.last_sample_us[i] = now();
    const bool started = run.status.start_time_us != 0;
    const double t = started ? (s.t_us - run.status.start_time_us) * 1e-6 : -1.0;
    const JointVector planned = trajectory.positionAt(std::max(t, 0.0));
    const double deviation = maxAbsDifference(s.q, planned);
    arm.planned = planned;
    arm.actual = s.q;
    arm.deviation = deviation;
    arm.max_deviation = std::max(arm.max_deviation, deviation);
    arm.last_sample_t = t;
    ++arm.samples;
    if (config_.trace_hz > 0 && s.t_us - run.last_trace_us[i] >= micros(1.0 / config_.trace_hz) &&
        run.traces[i].size() < config_.trace_max) {
      run.last_trace_us[i] = s.t_us;
      run.traces[i].push_back({t, planned, s.q});
    }
    // As the trajectory controller: the path tolerance holds until the arm's end time; after it the
    // goal tolerance and the goal time tolerance take over (the final report and the deadline).
    if (!isActive(run.status.state) || arm.done || t > arm.duration) continue;
    const ToleranceCheck check = checkTolerance(s.q, planned, arm.path_tolerance);
    if (check.violated) {
      const std::string what = "left its path: " + describeViolation(check, trajectory.joint_names, "path", t);
      if (arm.result == ResultCode::kSuccessful) {
        arm.result = ResultCode::kPathToleranceViolated;
        arm.message = what;
      }
      abortLocked(arm.robot + " " + what, DispatchState::kAborted);
      return;
    }
  }
}

void DispatchService::processStatusLocked(std::size_t i, const AgentReport& r) {
  Run& run = *run_;
  ArmDispatchStatus& arm = run.status.arms[i];
  const bool was_done = arm.done;
  arm.status = r.status;
  if (!isFinal(r.status) || was_done) {
    if (was_done && !isActive(run.status.state) && !run.status.final && allArmsDoneLocked()) finalizeLocked();
    return;
  }
  arm.done = true;
  if (arm.result == ResultCode::kSuccessful) {  // keep an earlier verdict (e.g. the server's deviation check)
    arm.result = r.result;
    arm.message = r.message;
  }
  if (run.status.state == DispatchState::kArming) return;  // dispatch() decides
  if (run.status.state == DispatchState::kRunning) {
    if (r.status == ArmStatus::kSucceeded && arm.result == ResultCode::kSuccessful) {
      const JointVector& goal = run.trajectories[i].points.back().positions;
      const ToleranceCheck off = arm.actual.size() > 0 ? checkTolerance(arm.actual, goal, arm.goal_tolerance)
                                                       : ToleranceCheck{};
      if (off.violated) {
        arm.result = ResultCode::kGoalToleranceViolated;
        arm.message = "ended off its goal: " + describeViolation(off, run.trajectories[i].joint_names, "goal",
                                                                 arm.last_sample_t);
        abortLocked(arm.robot + " " + arm.message, DispatchState::kFailed);
      } else if (allArmsDoneLocked()) {
        bool all_ok = std::all_of(run.status.arms.begin(), run.status.arms.end(), [](const ArmDispatchStatus& a) {
          return a.result == ResultCode::kSuccessful;
        });
        if (all_ok) finishLocked(DispatchState::kSucceeded, "");
      }
    } else if (r.status == ArmStatus::kFailed || arm.result != ResultCode::kSuccessful) {
      abortLocked(arm.robot + " failed: " + resultText(arm.result, arm.message), DispatchState::kFailed);
    } else {
      abortLocked(arm.robot + " stopped: " + resultText(r.result, r.message), DispatchState::kAborted);
    }
    return;
  }
  if (!run.status.final && allArmsDoneLocked()) finalizeLocked();
}

void DispatchService::abortLocked(const std::string& reason, DispatchState state) {
  if (!run_ || !isActive(run_->status.state)) return;
  Run& run = *run_;
  run.status.state = state;
  run.status.reason = reason;
  run.status.end_time_us = now();
  run.settle_deadline_us = run.status.end_time_us + micros(config_.settle_timeout);
  // Every connected agent, not only this dispatch's arms: an abort stops everything.
  pushToAllLocked(formatSse("abort", abortCommandToJson({run.status.id, reason})));
  for (ArmDispatchStatus& arm : run.status.arms) {
    auto it = controllers_.find(arm.robot);
    const bool connected = it != controllers_.end() && it->second.info.connected;
    if (!arm.done && !connected) {
      arm.done = true;
      if (arm.result == ResultCode::kSuccessful) {
        arm.result = ResultCode::kFault;
        arm.message = "the controller is not connected";
      }
    }
  }
  const DispatchStatus snapshot = snapshotLocked(false);
  noteLocked([snapshot, reason](DispatchListener& l) { l.onDispatchAborted(snapshot, reason); });
  if (allArmsDoneLocked()) finalizeLocked();
  cv_.notify_all();
}

void DispatchService::finishLocked(DispatchState state, const std::string& reason) {
  Run& run = *run_;
  run.status.state = state;
  run.status.reason = reason;
  run.status.end_time_us = now();
  finalizeLocked();
}

void DispatchService::finalizeLocked() {
  Run& run = *run_;
  if (run.status.final) return;
  for (ArmDispatchStatus& arm : run.status.arms) {
    if (arm.done) continue;
    arm.done = true;
    if (arm.result == ResultCode::kSuccessful) {
      arm.result = ResultCode::kFault;
      arm.message = "no final report from the controller";
    }
  }
  run.status.final = true;
  const DispatchStatus snapshot = snapshotLocked(false);
  noteLocked([snapshot](DispatchListener& l) { l.onDispatchFinished(snapshot); });
  cv_.notify_all();
}

DispatchStatus DispatchService::snapshotLocked(bool with_trace) const {
  DispatchStatus s = run_->status;
  if (s.start_time_us != 0) {
    const std::int64_t until = s.end_time_us != 0 ? s.end_time_us : now();
    s.elapsed = (until - s.start_time_us) * 1e-6;
  }
  if (with_trace) {
    for (std::size_t i = 0; i < s.arms.size(); ++i) s.arms[i].trace = run_->traces[i];
  }
  return s;
}

std::optional<DispatchStatus> DispatchService::status(bool with_trace) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!run_) return std::nullopt;
  return snapshotLocked(with_trace);
}

std::string DispatchService::newIdLocked() {
  return "d" + std::to_string(wallMillis()) + "-" + id_tag_ + "-" + std::to_string(next_dispatch_++);
}

void DispatchService::noteRefusedLocked(const Plan& plan, const DispatchOptions& options, const DispatchOrigin& origin,
                                        const PreflightReport& report, const std::string& reason) {
  DispatchStatus st;
  st.id = newIdLocked();
  st.origin = origin;
  st.state = DispatchState::kRefused;
  st.reason = reason;
  st.scene = plan.scene;
  st.planner = plan.planner;
  st.time_scale = options.time_scale;
  st.created_us = now();
  st.created_unix_ms = wallMillis();
  st.end_time_us = st.created_us;
  st.final = true;
  for (const RobotTrajectory& r : plan.robots) {
    ArmDispatchStatus arm;
    arm.robot = r.robot;
    auto it = controllers_.find(r.robot);
    if (it != controllers_.end()) arm.driver = it->second.info.driver;
    for (const PreflightCheck& c : report.checks) {
      if (!c.passed && c.robot == r.robot) arm.message += (arm.message.empty() ? "" : "; ") + c.message;
    }
    if (!r.points.empty()) arm.duration = (r.points.back().t - r.points.front().t) * options.time_scale;
    st.duration = std::max(st.duration, arm.duration);
    st.arms.push_back(std::move(arm));
  }
  noteLocked([st, report](DispatchListener& l) { l.onDispatchRefused(st, report); });
}

PreflightOptions DispatchService::preflightOptions(const DispatchOptions& options) const {
  PreflightOptions popts;
  popts.start_tolerance = options.start_tolerance.value_or(config_.start_tolerance);
  popts.time_scale = options.time_scale;
  popts.state_timeout = config_.state_timeout;
  popts.validate_geometry = options.validate_geometry.value_or(config_.validate_geometry);
  popts.validator_threads = config_.validator_threads;
  popts.now_us = now();
  return popts;
}

PreflightReport DispatchService::runChecks(const Plan& plan, const Scene& scene, const DispatchOptions& options,
                                           const std::vector<ControllerInfo>& snapshot) const {
  PreflightReport report;
  try {
    DASH_THROW_UNLESS(options.time_scale > 0.0 && std::isfinite(options.time_scale), "time_scale must be positive");
    report = runPreflight(scene, plan, snapshot, preflightOptions(options));
  } catch (const InputError& e) {
    report.passed = false;
    report.checks.push_back({"plan_valid", "", false, e.what(), 422});
  }
  return report;
}

PreflightReport DispatchService::check(const Plan& plan, const Scene& scene, const DispatchOptions& options) const {
  return runChecks(plan, scene, options, controllers());
}

bool DispatchService::sleepUnlessStopping(std::chrono::microseconds period) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return cv_.wait_for(lock, period, [&] { return stopping_; });
}

DispatchOutcome DispatchService::dispatch(const Plan& plan, const Scene& scene, const DispatchOptions& options,
                                          const DispatchOrigin& origin) {
  DispatchOutcome outcome;
  std::vector<ControllerInfo> snapshot;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (stopping_) {
      outcome.http_status = kUnavailable;
      outcome.error = "busy";
      outcome.reason = "the dispatch service is shutting down";
      return outcome;
    }
    if (preflight_in_progress_ || (run_ && isActive(run_->status.state))) {
      outcome.http_status = kConflict;
      outcome.error = "busy";
      outcome.reason = run_ && isActive(run_->status.state)
                           ? "dispatch " + run_->status.id + " is still " + dispatchStateName(run_->status.state)
                           : "another dispatch request is being checked";
      return outcome;
    }
    preflight_in_progress_ = true;
    for (const auto& [robot, entry] : controllers_) snapshot.push_back(entry.info);
  }
  struct ClearFlag {
    DispatchService* self;
    ~ClearFlag() {
      std::lock_guard<std::mutex> lock(self->mutex_);
      self->preflight_in_progress_ = false;
    }
  } clear_flag{this};

  const PreflightOptions popts = preflightOptions(options);
  outcome.preflight = runChecks(plan, scene, options, snapshot);
  if (!outcome.preflight.passed) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const PreflightReport report = outcome.preflight;
      noteLocked([report](DispatchListener& l) { l.onPreflight(report, ""); });
      noteRefusedLocked(plan, options, origin, report, report.reason());
    }
    drainNotes();
    outcome.http_status = outcome.preflight.httpStatus();
    outcome.error = "preflight";
    outcome.reason = outcome.preflight.reason();
    return outcome;
  }

  {
    std::unique_lock<std::mutex> lock(mutex_);
    // The agents may have changed while the validator ran.
    for (const ArmTrajectory& t : outcome.preflight.trajectories) {
      auto before = std::find_if(snapshot.begin(), snapshot.end(), [&](const ControllerInfo& c) { return c.robot == t.robot; });
      auto it = controllers_.find(t.robot);
      if (it == controllers_.end() || !it->second.info.connected || before == snapshot.end() ||
          it->second.info.session != before->session) {
        outcome.http_status = kConflict;
        outcome.error = "preflight";
        outcome.reason = t.robot + ": the controller disconnected during the pre-flight checks";
        noteRefusedLocked(plan, options, origin, outcome.preflight, outcome.reason);
        lock.unlock();
        drainNotes();
        return outcome;
      }
    }
    Run run;
    DispatchStatus& st = run.status;
    st.id = newIdLocked();
    st.origin = origin;
    st.state = DispatchState::kArming;
    st.scene = plan.scene;
    st.planner = plan.planner;
    st.time_scale = options.time_scale;
    st.created_us = now();
    st.created_unix_ms = wallMillis();
    st.path_tolerance = options.path_tolerance.value_or(config_.path_tolerance);
    st.start_tolerance = popts.start_tolerance;
    st.goal_tolerance = options.goal_tolerance.value_or(config_.goal_tolerance);
    st.goal_time_tolerance = options.goal_time_tolerance.value_or(config_.goal_time_tolerance);
    for (const ArmTrajectory& t : outcome.preflight.trajectories) {
      ArmDispatchStatus arm;
      arm.robot = t.robot;
      arm.path_tolerance = st.path_tolerance.resolve(t.joint_names);
      arm.goal_tolerance = st.goal_tolerance.resolve(t.joint_names);
      const GoalLimits limits{st.start_tolerance, arm.goal_tolerance, st.goal_time_tolerance};
      arm.driver = controllers_[t.robot].info.driver;
      arm.duration = t.endTime();
      arm.planned = t.points.front().positions;
      st.duration = std::max(st.duration, arm.duration);
      st.arms.push_back(arm);
      run.trajectories.push_back(t);
      run.traces.emplace_back();
      run.last_trace_us.push_back(0);
      run.last_sample_us.push_back(0);
      controllers_[t.robot].stream->push(formatSse("trajectory", trajectoryCommandToJson({st.id, t, limits})));
    }
    run_ = std::move(run);
    const std::string id = run_->status.id;
    const PreflightReport report = outcome.preflight;
    noteLocked([report, id](DispatchListener& l) { l.onPreflight(report, id); });

    const auto deadline = std::chrono::steady_clock::now() + std::chrono::microseconds(micros(config_.arm_timeout));
    auto settled = [&] {
      if (stopping_ || run_->status.state != DispatchState::kArming) return true;
      bool all_armed = true;
      for (const ArmDispatchStatus& a : run_->status.arms) {
        if (a.done) return true;  // refused (or aborted)
        all_armed = all_armed && a.status == ArmStatus::kArmed;
      }
      return all_armed;
    };
    cv_.wait_until(lock, deadline, settled);

    Run& r = *run_;
    if (r.status.state != DispatchState::kArming || stopping_) {
      outcome.http_status = kConflict;
      outcome.error = "aborted";
      outcome.reason = stopping_ ? "the dispatch service is shutting down" : r.status.reason;
    } else {
      std::string refusal;
      bool timed_out = false;
      for (const ArmDispatchStatus& a : r.status.arms) {
        if (a.done) {
          refusal = a.robot + " refused its goal: " + resultText(a.result, a.message);
          break;
        }
      }
      if (refusal.empty()) {
        for (const ArmDispatchStatus& a : r.status.arms) {
          if (a.status != ArmStatus::kArmed) {
            refusal = a.robot + " did not accept its goal within " + fmt(config_.arm_timeout, 1) + " s";
            timed_out = true;
            break;
          }
        }
      }
      if (!refusal.empty()) {
        r.status.state = DispatchState::kRefused;
        r.status.reason = refusal;
        r.status.end_time_us = now();
        for (ArmDispatchStatus& a : r.status.arms) {
          auto it = controllers_.find(a.robot);
          if (it != controllers_.end() && it->second.stream) {
            it->second.stream->push(formatSse("abort", abortCommandToJson({r.status.id, "dispatch refused: " + refusal})));
          }
          if (!a.done) {  // armed (or silent): its goal is dropped, nothing moved
            a.done = true;
            a.result = ResultCode::kCancelled;
            a.message = "dispatch refused";
          }
        }
        finalizeLocked();
        outcome.http_status = timed_out ? kGatewayTimeout : kConflict;
        outcome.error = timed_out ? "timeout" : "refused";
        outcome.reason = refusal;
      } else {
        const double delay = options.start_delay.value_or(config_.start_delay);
        r.status.start_time_us = now() + micros(std::max(delay, 0.0));
        r.status.state = DispatchState::kRunning;
        r.deadline_us = r.status.start_time_us + micros(r.status.duration + r.status.goal_time_tolerance + kDeadlineSlack);
        for (std::int64_t& last : r.last_sample_us) last = std::max(last, r.status.start_time_us);
        for (const ArmDispatchStatus& a : r.status.arms) {
          controllers_[a.robot].stream->push(formatSse("start", startCommandToJson({r.status.id, r.status.start_time_us})));
        }
        const DispatchStatus started = snapshotLocked(false);
        noteLocked([started](DispatchListener& l) { l.onDispatchStarted(started); });
        outcome.accepted = true;
        outcome.http_status = kAccepted;
      }
    }
    outcome.status = snapshotLocked(false);
  }
  drainNotes();
  return outcome;
}

AbortOutcome DispatchService::abort(const std::string& reason) {
  AbortOutcome out;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    out.at_us = now();
    const std::string text = reason.empty() ? "abort requested" : reason;
    if (run_ && isActive(run_->status.state)) {
      out.had_dispatch = true;
      out.dispatch_id = run_->status.id;
      abortLocked(text, DispatchState::kAborted);  // pushes to every connected agent
      for (const auto& [robot, entry] : controllers_) out.controllers_notified += entry.info.connected ? 1 : 0;
    } else {
      out.controllers_notified = pushToAllLocked(formatSse("abort", abortCommandToJson({"", text})));
    }
  }
  cv_.notify_all();
  drainNotes();
  return out;
}

// ---------------------------------------------------------------- monitor

void DispatchService::checkArmsLocked() {
  Run& run = *run_;
  const std::int64_t t = now();
  if (isActive(run.status.state)) {
    for (ArmDispatchStatus& arm : run.status.arms) {
      if (arm.done) continue;
      const ControllerEntry& entry = controllers_[arm.robot];
      const double silent = (t - entry.info.last_report_us) * 1e-6;
      if (!entry.info.connected || silent > config_.state_timeout) {
        arm.done = true;
        arm.result = ResultCode::kFault;
        arm.message = entry.info.connected ? "no state report for " + fmt(silent, 2) + " s" : "the controller disconnected";
        abortLocked(arm.robot + ": " + arm.message, DispatchState::kAborted);
        return;
      }
      // Reports without joint states (a driver that lost its robot's state) are no better.
      const auto index = static_cast<std::size_t>(&arm - run.status.arms.data());
      const double unseen = (t - run.last_sample_us[index]) * 1e-6;
      if (run.status.state == DispatchState::kRunning && t > run.status.start_time_us && unseen > config_.sample_timeout) {
        arm.done = true;
        arm.result = ResultCode::kFault;
        arm.message = "no joint state for " + fmt(unseen, 2) + " s";
        abortLocked(arm.robot + ": " + arm.message, DispatchState::kAborted);
        return;
      }
    }
    if (run.status.state == DispatchState::kRunning && t > run.deadline_us) {
      for (ArmDispatchStatus& arm : run.status.arms) {
        if (arm.done) continue;
        arm.result = ResultCode::kGoalToleranceViolated;
        arm.message = "not at its goal " + fmt(run.status.goal_time_tolerance, 2) + " s after its end time";
        abortLocked(arm.robot + " " + arm.message, DispatchState::kFailed);
        return;
      }
    }
  } else if (!run.status.final && (t > run.settle_deadline_us || allArmsDoneLocked())) {
    finalizeLocked();
  }
}

void DispatchService::monitorLoop() {
  const auto period = std::chrono::microseconds(micros(config_.monitor_period));
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait_for(lock, period, [&] { return stopping_; });
      if (stopping_) break;
      if (run_) checkArmsLocked();
    }
    drainNotes();
  }
}

}  // namespace dash::dispatch
