// DispatchService, while arms move: samples against the plan, agents' final reports, deadlines and
// silences (dispatch_service.h). Execution by dependencies has its own in dispatch_tpg.cpp.
#include <algorithm>

#include "server/dispatch/dispatch_service.h"
#include "server/dispatch/dispatch_service_util.h"

namespace dash::dispatch {

using namespace service_detail;

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
    // By dependencies: the nearest point of the step's own path (no clock); else the timetable's.
    const JointVector planned = run.tpg ? run.tpg->nearestPlanned(static_cast<int>(i), s.q)
                                        : trajectory.positionAt(std::max(t, 0.0));
    if (planned.size() != dof) continue;
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
    if (!isActive(run.status.state) || arm.done || (!run.tpg && t > arm.duration)) continue;
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
    if (run.tpg) {
      if (run.status.state == DispatchState::kRunning) checkTpgDeadlinesLocked();
    } else if (run.status.state == DispatchState::kRunning && t > run.deadline_us) {
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
