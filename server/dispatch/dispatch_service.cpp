#include "server/dispatch/dispatch_service.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "engine/core/check.h"
#include "server/dispatch/dispatch_service_util.h"

namespace dash::dispatch {

using namespace service_detail;

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
  settleIdleTpgArmsLocked();
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
  fillTpgStatusLocked(s);
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

DispatchStatus DispatchService::newStatusLocked(const Plan& plan, const DispatchOptions& options,
                                                const DispatchOrigin& origin, DispatchState state) {
  DispatchStatus st;
  st.id = newIdLocked();
  st.origin = origin;
  st.state = state;
  st.scene = plan.scene;
  st.planner = plan.planner;
  st.execution = options.execution;
  st.time_scale = options.time_scale;
  st.created_us = now();
  st.created_unix_ms = wallMillis();
  return st;
}

void DispatchService::noteRefusedLocked(const Plan& plan, const DispatchOptions& options, const DispatchOrigin& origin,
                                        const PreflightReport& report, const std::string& reason) {
  DispatchStatus st = newStatusLocked(plan, options, origin, DispatchState::kRefused);
  st.reason = reason;
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
  PreflightReport report = runChecks(plan, scene, options, controllers());
  if (report.passed && options.execution == "tpg") tpgGraph(plan, scene, options, report);
  return report;
}

bool DispatchService::sleepUnlessStopping(std::chrono::microseconds period) const {
  std::unique_lock<std::mutex> lock(mutex_);
  return cv_.wait_for(lock, period, [&] { return stopping_; });
}

bool DispatchService::beginRequestLocked(DispatchOutcome& outcome, std::vector<ControllerInfo>& snapshot) {
  if (stopping_) {
    outcome.http_status = kUnavailable;
    outcome.error = "busy";
    outcome.reason = "the dispatch service is shutting down";
    return false;
  }
  if (preflight_in_progress_ || (run_ && isActive(run_->status.state))) {
    outcome.http_status = kConflict;
    outcome.error = "busy";
    outcome.reason = run_ && isActive(run_->status.state)
                         ? "dispatch " + run_->status.id + " is still " + dispatchStateName(run_->status.state)
                         : "another dispatch request is being checked";
    return false;
  }
  preflight_in_progress_ = true;
  for (const auto& [robot, entry] : controllers_) snapshot.push_back(entry.info);
  return true;
}

bool DispatchService::agentsUnchangedLocked(const std::vector<ControllerInfo>& snapshot, DispatchOutcome& outcome) {
  for (const ArmTrajectory& t : outcome.preflight.trajectories) {
    auto before = std::find_if(snapshot.begin(), snapshot.end(), [&](const ControllerInfo& c) { return c.robot == t.robot; });
    auto it = controllers_.find(t.robot);
    if (it == controllers_.end() || !it->second.info.connected || before == snapshot.end() ||
        it->second.info.session != before->session) {
      outcome.http_status = kConflict;
      outcome.error = "preflight";
      outcome.reason = t.robot + ": the controller disconnected during the pre-flight checks";
      return false;
    }
  }
  return true;
}

void DispatchService::newRunLocked(const Plan& plan, const DispatchOptions& options, const DispatchOrigin& origin,
                                   const PreflightReport& preflight) {
  Run run;
  run.status = newStatusLocked(plan, options, origin, DispatchState::kArming);
  DispatchStatus& st = run.status;
  st.path_tolerance = options.path_tolerance.value_or(config_.path_tolerance);
  st.start_tolerance = options.start_tolerance.value_or(config_.start_tolerance);
  st.goal_tolerance = options.goal_tolerance.value_or(config_.goal_tolerance);
  st.goal_time_tolerance = options.goal_time_tolerance.value_or(config_.goal_time_tolerance);
  for (const ArmTrajectory& t : preflight.trajectories) {
    ArmDispatchStatus arm;
    arm.robot = t.robot;
    arm.path_tolerance = st.path_tolerance.resolve(t.joint_names);
    arm.goal_tolerance = st.goal_tolerance.resolve(t.joint_names);
    arm.driver = controllers_[t.robot].info.driver;
    arm.duration = t.endTime();
    arm.planned = t.points.front().positions;
    st.duration = std::max(st.duration, arm.duration);
    st.arms.push_back(arm);
    run.trajectories.push_back(t);
    run.traces.emplace_back();
    run.last_trace_us.push_back(0);
    run.last_sample_us.push_back(0);
  }
  run_ = std::move(run);
  const std::string id = run_->status.id;
  noteLocked([preflight, id](DispatchListener& l) { l.onPreflight(preflight, id); });
}

DispatchOutcome DispatchService::dispatch(const Plan& plan, const Scene& scene, const DispatchOptions& options,
                                          const DispatchOrigin& origin) {
  DispatchOutcome outcome;
  std::vector<ControllerInfo> snapshot;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!beginRequestLocked(outcome, snapshot)) return outcome;
  }
  struct ClearFlag {
    DispatchService* self;
    ~ClearFlag() {
      std::lock_guard<std::mutex> lock(self->mutex_);
      self->preflight_in_progress_ = false;
    }
  } clear_flag{this};

  outcome.preflight = runChecks(plan, scene, options, snapshot);
  std::optional<tpg::Graph> graph;
  if (outcome.preflight.passed && options.execution == "tpg") graph = tpgGraph(plan, scene, options, outcome.preflight);
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
    if (!agentsUnchangedLocked(snapshot, outcome)) {
      noteRefusedLocked(plan, options, origin, outcome.preflight, outcome.reason);
    } else {
      newRunLocked(plan, options, origin, outcome.preflight);
      if (graph) {
        startTpgLocked(plan, *graph, outcome);
      } else {
        armAndStartLocked(lock, options, outcome);
      }
      outcome.status = snapshotLocked(false);
    }
  }
  drainNotes();
  return outcome;
}

void DispatchService::armAndStartLocked(std::unique_lock<std::mutex>& lock, const DispatchOptions& options,
                                        DispatchOutcome& outcome) {
  Run& r = *run_;
  for (std::size_t i = 0; i < r.trajectories.size(); ++i) {
    const ArmDispatchStatus& a = r.status.arms[i];
    const GoalLimits limits{r.status.start_tolerance, a.goal_tolerance, r.status.goal_time_tolerance};
    controllers_[a.robot].stream->push(formatSse("trajectory", trajectoryCommandToJson({r.status.id, r.trajectories[i], limits})));
  }
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
  if (r.status.state != DispatchState::kArming || stopping_) {
    outcome.http_status = kConflict;
    outcome.error = "aborted";
    outcome.reason = stopping_ ? "the dispatch service is shutting down" : r.status.reason;
    return;
  }
  bool timed_out = false;
  const std::string refusal = armingRefusalLocked(timed_out);
  if (!refusal.empty()) {
    refuseArmedLocked(refusal);
    outcome.http_status = timed_out ? kGatewayTimeout : kConflict;
    outcome.error = timed_out ? "timeout" : "refused";
    outcome.reason = refusal;
    return;
  }
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

std::string DispatchService::armingRefusalLocked(bool& timed_out) const {
  for (const ArmDispatchStatus& a : run_->status.arms) {
    if (a.done) return a.robot + " refused its goal: " + resultText(a.result, a.message);
  }
  for (const ArmDispatchStatus& a : run_->status.arms) {
    if (a.status != ArmStatus::kArmed) {
      timed_out = true;
      return a.robot + " did not accept its goal within " + fmt(config_.arm_timeout, 1) + " s";
    }
  }
  return "";
}

void DispatchService::refuseArmedLocked(const std::string& refusal) {
  Run& r = *run_;
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

}  // namespace dash::dispatch
