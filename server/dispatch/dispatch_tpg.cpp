// DispatchService, execution by dependencies (`options.execution: "tpg"`, tpg_execution.h): the
// graph and its pre-flight check, releasing each arm's next step when what it waits for is done,
// the agents' step reports, per-step deadlines, and the per-arm view of the graph in the status.
#include <algorithm>

#include "engine/core/check.h"
#include "engine/tpg/tpg_replay.h"
#include "server/dispatch/dispatch_service.h"
#include "server/dispatch/dispatch_service_util.h"

namespace dash::dispatch {

using namespace service_detail;

namespace {

/// Random delay draws replayed and certified before a dispatch by dependencies. The graph builder
/// does not yet prove every pair apart (docs/dispatch.md, "Known gap": a handover's gripper and held
/// object may come into each other when both arms approach at once; 49 of 100 draws of a 4-arm
/// sorting plan failed), so no arm moves on a graph whose replays the certified validator refuses.
/// A guard, not a proof: a graph that fails one draw in two passes 8 draws with probability 1/256.
constexpr int kPreflightReplayDraws = 8;

}  // namespace

std::optional<tpg::Graph> DispatchService::tpgGraph(const Plan& plan, const Scene& scene, const DispatchOptions& options,
                                                    PreflightReport& report) const {
  PreflightCheck check{"tpg_graph", "", true, "", 200};
  std::optional<tpg::Graph> graph;
  try {
    graph = plan.tpg.empty() ? tpg::buildGraph(scene, plan) : tpg::parseTpg(plan.tpg, plan);
    DASH_THROW_UNLESS(graph->forced == 0, "the temporal plan graph orders " + std::to_string(graph->forced) +
                                              " pairs of segments that run at once in the plan and meet: it cannot "
                                              "prove them apart, so the plan cannot run by dependencies");
    std::vector<std::string> robots;
    for (const RobotTrajectory& r : plan.robots) robots.push_back(r.robot);
    const TpgRun steps(plan, *graph, robots, options.time_scale, "");
    double ratio = 0.0;
    for (int arm = 0; arm < steps.arms(); ++arm) {
      const int r = scene.robotIndex(robots[static_cast<std::size_t>(arm)]);
      DASH_THROW_UNLESS(r >= 0, robots[static_cast<std::size_t>(arm)] + " is not in the scene");
      const JointVector& limit = scene.robots[static_cast<std::size_t>(r)].model->limits.velocity_max;
      for (const TpgStep& step : steps.steps(arm)) {
        if (step.kind == TpgStep::Kind::kMotion) ratio = std::max(ratio, peakSpeed(step.goal, limit).ratio);
      }
    }
    DASH_THROW_UNLESS(ratio <= 1.0 + 1e-6, "a segment, which starts and ends at rest, would move a joint at " +
                                               fmt(ratio * 100.0, 1) + " % of its limit: time_scale >= " +
                                               fmt(options.time_scale * ratio * 1.001, 3) + " passes");
    tpg::ReplayOptions replay;
    replay.draws = kPreflightReplayDraws;
    const tpg::ReplayReport replays = tpg::checkReplays(scene, plan, *graph, replay);
    DASH_THROW_UNLESS(replays.failed == 0,
                      std::to_string(replays.failed) + " of " + std::to_string(replays.draws) +
                          " replays with random delays that respect the temporal plan graph fail the certified "
                          "validator (first: " + replays.first_problem + "): the plan cannot run by dependencies");
    check.message = std::to_string(graph->nodes.size()) + " nodes, " + std::to_string(graph->edges.size()) +
                    " edges; " + std::to_string(replays.draws) + " delayed replays certified";
  } catch (const InputError& e) {
    check.passed = false;
    check.message = e.what();
    check.http_status = kUnprocessable;
    graph.reset();
  }
  report.checks.push_back(check);
  if (!check.passed) report.passed = false;
  return graph;
}

void DispatchService::startTpgLocked(const Plan& plan, const tpg::Graph& graph, DispatchOutcome& outcome) {
  Run& r = *run_;
  std::vector<std::string> robots;
  for (const ArmDispatchStatus& a : r.status.arms) robots.push_back(a.robot);
  r.tpg.emplace(plan, graph, robots, r.status.time_scale, r.status.id);
  r.status.start_time_us = now();
  r.status.state = DispatchState::kRunning;
  for (std::int64_t& last : r.last_sample_us) last = std::max(last, r.status.start_time_us);
  for (std::size_t i = 0; i < r.status.arms.size(); ++i) {
    const auto& steps = r.tpg->steps(static_cast<int>(i));
    r.status.arms[i].steps = static_cast<int>(steps.size());
    r.status.arms[i].duration = steps.empty() ? 0.0 : steps.back().planned_end;
  }
  const DispatchStatus started = snapshotLocked(false);
  noteLocked([started](DispatchListener& l) { l.onDispatchStarted(started); });
  releaseTpgLocked();
  outcome.accepted = true;
  outcome.http_status = kAccepted;
}

void DispatchService::releaseTpgLocked() {
  Run& r = *run_;
  if (!r.tpg || r.status.state != DispatchState::kRunning) return;
  for (bool progressed = true; progressed;) {
    progressed = false;
    for (int i = 0; i < r.tpg->arms(); ++i) {
      ArmDispatchStatus& arm = r.status.arms[static_cast<std::size_t>(i)];
      const int k = r.tpg->current(i);
      if (k >= static_cast<int>(r.tpg->steps(i).size()) || !r.tpg->mayStart(i)) continue;
      TpgStep& step = r.tpg->steps(i)[static_cast<std::size_t>(k)];
      if (step.state != TpgStep::State::kPending) continue;
      step.start_us = now();
      step.q_start = arm.actual;
      if (step.kind == TpgStep::Kind::kHold || step.kind == TpgStep::Kind::kInspect) {  // nothing to send
        step.state = TpgStep::State::kDone;
        step.end_us = step.start_us;
        step.q_end = arm.actual;
        progressed = true;
        continue;
      }
      const double time_tolerance = step.kind == TpgStep::Kind::kGripper
                                        ? std::max(r.status.goal_time_tolerance, config_.gripper_allowance)
                                        : r.status.goal_time_tolerance;
      const GoalLimits limits{r.status.start_tolerance, arm.goal_tolerance, time_tolerance};
      const auto stream = controllers_[arm.robot].stream;
      if (stream) {
        stream->push(formatSse("trajectory", trajectoryCommandToJson({step.goal_id, step.goal, limits})));
        stream->push(formatSse("start", startCommandToJson({step.goal_id, step.start_us})));
      }
      step.state = TpgStep::State::kSent;
    }
  }
  for (int i = 0; i < r.tpg->arms(); ++i) {
    ArmDispatchStatus& arm = r.status.arms[static_cast<std::size_t>(i)];
    if (r.tpg->armDone(i) && !arm.done) {
      arm.done = true;
      arm.status = ArmStatus::kSucceeded;
    }
  }
  if (r.tpg->allDone()) finishLocked(DispatchState::kSucceeded, "");
}

void DispatchService::processTpgStatusLocked(std::size_t i, const AgentReport& report) {
  Run& run = *run_;
  ArmDispatchStatus& arm = run.status.arms[i];
  const int arm_index = static_cast<int>(i);
  const int k = run.tpg->stepOfGoal(arm_index, report.dispatch_id);
  if (k < 0) return;
  TpgStep& step = run.tpg->steps(arm_index)[static_cast<std::size_t>(k)];
  if (step.state != TpgStep::State::kSent) return;
  arm.status = report.status;
  if (!isFinal(report.status)) return;
  if (!isActive(run.status.state)) {  // after an abort: the arm's last word
    if (!arm.done) {
      arm.done = true;
      if (arm.result == ResultCode::kSuccessful) {
        arm.result = report.result;
        arm.message = report.message;
      }
    }
    if (!run.status.final && allArmsDoneLocked()) finalizeLocked();
    return;
  }
  if (report.status == ArmStatus::kSucceeded && report.result == ResultCode::kSuccessful) {
    step.state = TpgStep::State::kDone;
    step.end_us = now();
    step.q_end = arm.actual;
    releaseTpgLocked();
    return;
  }
  arm.done = true;
  arm.result = report.result == ResultCode::kSuccessful ? ResultCode::kFault : report.result;
  arm.message = "step " + std::to_string(k) + " (" + tpgStepKindName(step.kind) + "): " + report.message;
  abortLocked(arm.robot + " failed: " + resultText(arm.result, arm.message),
              report.status == ArmStatus::kFailed ? DispatchState::kFailed : DispatchState::kAborted);
}

bool DispatchService::checkTpgDeadlinesLocked() {
  Run& run = *run_;
  const std::int64_t t = now();
  for (int i = 0; i < run.tpg->arms(); ++i) {
    const int k = run.tpg->current(i);
    if (k >= static_cast<int>(run.tpg->steps(i).size())) continue;
    const TpgStep& step = run.tpg->steps(i)[static_cast<std::size_t>(k)];
    if (step.state != TpgStep::State::kSent) continue;
    const double allowed =
        run.tpg->allowance(step, config_.segment_time_factor, config_.segment_time_margin, config_.gripper_allowance);
    if ((t - step.start_us) * 1e-6 <= allowed) continue;
    ArmDispatchStatus& arm = run.status.arms[static_cast<std::size_t>(i)];
    arm.result = ResultCode::kGoalToleranceViolated;
    arm.message = "step " + std::to_string(k) + " (" + tpgStepKindName(step.kind) + ") not done after " +
                  fmt(allowed, 1) + " s (planned " + fmt(step.planned_end - step.planned_start, 2) + " s)";
    abortLocked(arm.robot + " " + arm.message, DispatchState::kFailed);
    return true;
  }
  return false;
}

void DispatchService::settleIdleTpgArmsLocked() {
  Run& run = *run_;
  if (!run.tpg) return;
  for (int i = 0; i < run.tpg->arms(); ++i) {
    ArmDispatchStatus& arm = run.status.arms[static_cast<std::size_t>(i)];
    const int k = run.tpg->current(i);
    const bool running = k < static_cast<int>(run.tpg->steps(i).size()) &&
                         run.tpg->steps(i)[static_cast<std::size_t>(k)].state == TpgStep::State::kSent;
    if (arm.done || running) continue;
    arm.done = true;
    if (arm.result == ResultCode::kSuccessful) {
      arm.result = ResultCode::kCancelled;
      arm.message = "stopped while waiting between steps";
    }
  }
}

void DispatchService::fillTpgStatusLocked(DispatchStatus& status) const {
  const Run& run = *run_;
  if (!run.tpg) return;
  std::vector<std::string> robots;
  for (const ArmDispatchStatus& a : status.arms) robots.push_back(a.robot);
  for (int i = 0; i < run.tpg->arms(); ++i) {
    ArmDispatchStatus& arm = status.arms[static_cast<std::size_t>(i)];
    arm.step = run.tpg->current(i);
    arm.steps = static_cast<int>(run.tpg->steps(i).size());
    const bool pending = arm.step < arm.steps &&
                         run.tpg->steps(i)[static_cast<std::size_t>(arm.step)].state == TpgStep::State::kPending;
    arm.waiting_for = pending && isActive(status.state) ? run.tpg->waitingFor(i, robots) : "";
    arm.segments = run.tpg->records(i, status.start_time_us);
  }
}

}  // namespace dash::dispatch
