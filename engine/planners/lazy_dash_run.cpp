#include "engine/planners/lazy_dash_run.h"

#include <algorithm>
#include <utility>

#include "engine/plan/plan_validator.h"

namespace dash {

namespace {

constexpr double kBudgetGrowth = 4.0;
constexpr int kMaxHomeBudgetGrowths = 3;
constexpr int kMaxBudgetGrowths = 3;   // after lifted motion bans: at most 64x the first budget
constexpr int kMaxRestartGrowths = 3;  // restarts that also grow the roadmap budgets

PlanOutcome timeoutOutcome(const Deadline& deadline) {
  return deadline.stopRequested() ? PlanOutcome::kCancelled : PlanOutcome::kTimeout;
}

MotionRound stopped(PlanOutcome outcome, std::string message) {
  MotionRound r;
  r.kind = MotionRound::Kind::kStopped;
  r.outcome = outcome;
  r.message = std::move(message);
  return r;
}

MotionRound failed(MotionFailure failure) {
  MotionRound r;
  r.kind = MotionRound::Kind::kFailed;
  r.failure = std::move(failure);
  return r;
}

/// A collision between robots, held objects or resting objects (what conflict resolution checks).
bool isContact(const ValidationProblem& problem) {
  return problem.kind == ProblemKind::kRobotRobotCollision || problem.kind == ProblemKind::kHeldObjectCollision ||
         problem.kind == ProblemKind::kRobotObjectCollision;
}

int robotIndex(const Scene& scene, const std::string& id) {
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r)
    if (scene.robots[r].id == id) return r;
  return -1;
}

/// A motion failure at `step` goes back to the task query as a one-query ban on that hyperarc.
TaskConstraint motionFeedback(const TaskPlan& plan, int step, const std::string& why) {
  TaskConstraint c;
  c.kind = TaskConstraint::Kind::kInteraction;
  c.arc = plan.steps[step].arc;
  c.temporary = true;
  c.from_motion = true;
  c.cause = why;
  return c;
}

}  // namespace

LazyDashRun::LazyDashRun(const Scene& scene, const LazyDashParams& params, const PlannerSettings& settings,
                         const Deadline& deadline, log::EventEmitter& emitter, std::string planner_name)
    : scene_(scene),
      params_(params),
      settings_(settings),
      deadline_(deadline),
      emitter_(emitter),
      planner_name_(std::move(planner_name)),
      world_(scene, {.clearance = params.clearance}),
      context_(world_),
      task_(scene, world_, context_, emitter, settings.seed, params.task),
      motion_(world_, context_, emitter, params.motion),
      scheduler_(world_, context_, params.scheduler) {
  scheduler_.reportProgress(&emitter_);  // steps scheduled, for people watching (reporting only)
  motion_.respect(&motion_constraints_);
  scheduler_.respect(&motion_constraints_);
}

PlanResult LazyDashRun::run() {
  emitter_.counter("restarts", 0);
  for (;;) {  // Algorithm 1, line 3
    if (task_plans_ == params_.max_task_plans) {
      const std::string why = "gave up after " + std::to_string(params_.max_task_plans) + " task plans";
      if (!restart(why)) return giveUp(why);
    }
    ++task_plans_;
    TaskLayerResult layer = task_.plan(deadline_);  // lines 4-7
    if (layer.status != TaskLayerStatus::kFeasible) {
      const std::string why =
          "task layer: " + std::string(toString(layer.status)) + (layer.reason.empty() ? "" : " (" + layer.reason + ")");
      if (layer.status == TaskLayerStatus::kTimeout) return finish(timeoutOutcome(deadline_), why);
      if (layer.status != TaskLayerStatus::kInfeasible || layer.no_route_in_task_hypergraph)
        return finish(PlanOutcome::kInfeasible, why);  // proven
      if (restart(why)) continue;
      return giveUp(why);
    }
    // No schedule avoids the hyperarcs the motion layer failed on: search harder on the same ones.
    if (layer.motion_bans_lifted && params_.budget_growth && budget_growths_ < kMaxBudgetGrowths) {
      ++budget_growths_;
      motion_.scaleBudget(kBudgetGrowth);
    }
    if (settings_.task_only) {
      result_.task_plan_json = layer.plan.toJson(task_.space());
      return finish(PlanOutcome::kSolved, layer.plan.describe(task_.space()));
    }
    if (!motionLoop(layer)) return std::move(result_);
  }
}

std::optional<LazyDashRun::Inner> LazyDashRun::motionLoop(TaskLayerResult& layer) {
  std::optional<MotionLayerResult> motions;
  plan_rechecks_ = 0;
  for (int motion_round = 0;; ++motion_round) {  // line 8: while S_T valid and S_M not valid
    MotionRound round = motionRound(layer, motions);
    if (round.kind == MotionRound::Kind::kSolved) {
      result_.stats.makespan = round.plan.makespan;
      result_.stats.path_length = round.plan.jointPathLength();
      result_.plan = std::move(round.plan);
      finish(PlanOutcome::kSolved, "solved");
      return std::nullopt;
    }
    if (round.kind == MotionRound::Kind::kStopped) {
      if (round.outcome != PlanOutcome::kInfeasible) {
        finish(round.outcome, std::move(round.message));
        return std::nullopt;
      }
      if (restart(round.message)) return Inner::kRestarted;
      giveUp(std::move(round.message));
      return std::nullopt;
    }
    const std::optional<bool> stay = feedback(round.failure, layer, motions, motion_round);
    if (!stay) {
      const std::string why = round.failure.where == MotionFailure::Where::kValidation
                                  ? "internal error: the planned schedule failed validation: " + round.failure.constraint.cause
                                  : round.failure.constraint.cause;
      if (restart(why)) return Inner::kRestarted;
      giveUp(why);
      return std::nullopt;
    }
    emitter_.setIteration(emitter_.iteration() + 1);
    if (!*stay) return Inner::kNextTaskPlan;  // lines 14-15: a task constraint, back to the task query
  }
}

MotionRound LazyDashRun::motionRound(TaskLayerResult& layer, std::optional<MotionLayerResult>& motions) {
  if (auto ended = motionQuery(layer, motions)) return std::move(*ended);
  ScheduleResult schedule = resolveConflicts(layer, *motions);
  if (!schedule.ok) return conflictFailure(layer, *motions, schedule);
  return validate(layer, schedule);
}

std::optional<MotionRound> LazyDashRun::motionQuery(const TaskLayerResult& layer,
                                                    std::optional<MotionLayerResult>& motions) {
  if (!motions) motions = motion_.plan(layer.plan, layer.transitions, task_.space(), deadline_);
  if (motions->status == MotionStatus::kTimeout) return stopped(timeoutOutcome(deadline_), "motion layer: timeout");
  if (motions->status == MotionStatus::kOk) return std::nullopt;
  MotionFailure f;
  f.where = MotionFailure::Where::kMotionQuery;
  f.step = motions->failed_step;
  f.constraint.cause = "motion query: " + motions->reason;
  if (f.step >= 0) {
    f.constraint.histories = {lazy::historyOf(layer.plan, motions->failed_robot, f.step)};
    f.constraint.configurations = {{motions->failed_robot, motions->failed_q}};
    f.resampleable = motions->ends_free;
  }
  motions.reset();
  return failed(std::move(f));
}

ScheduleResult LazyDashRun::resolveConflicts(const TaskLayerResult& layer, const MotionLayerResult& motions) {
  log::PhaseTimer timer(emitter_, log::Phase::ConflictResolution);
  const MoveReplanner replan = [&](int r, const JointVector& from, const JointVector& to, const MotionContext& ctx) {
    return motion_.connect(r, from, to, ctx, deadline_);
  };
  ScheduleResult schedule = scheduler_.build(layer.plan, layer.transitions, motions, task_.space(), replan, deadline_);
  reused_steps_ += schedule.stats.reused_steps;
  emitter_.counter("scheduled_steps_reused", reused_steps_);
  return schedule;
}

MotionRound LazyDashRun::conflictFailure(const TaskLayerResult& layer, const MotionLayerResult& motions,
                                         const ScheduleResult& schedule) {
  if (deadline_.expired()) return stopped(timeoutOutcome(deadline_), "conflict resolution: timeout");
  if (schedule.failed_step < 0) return stopped(PlanOutcome::kInfeasible, "conflict resolution: " + schedule.reason);
  MotionFailure f;
  f.where = MotionFailure::Where::kConflictResolution;
  f.step = schedule.failed_step;
  f.constraint.cause = "conflict resolution: " + schedule.reason;
  const TaskArc& a = layer.plan.steps[f.step].action;
  const TransitionConfig& tc = layer.transitions[f.step];
  f.constraint.histories = {lazy::historyOf(layer.plan, a.robot, f.step)};
  f.constraint.configurations = {{a.robot, tc.q}};
  if (a.type == TaskArcType::kHandover) {
    f.constraint.histories.push_back(lazy::historyOf(layer.plan, a.robot2, f.step));
    f.constraint.configurations.push_back({a.robot2, tc.q2});
    f.resampleable = true;  // another handover configuration (pose, IK branches), when the region does not do
  }
  // C_M = (Pi_1, Pi_2, p): a region to replan around, unless the constrained move starts or ends inside
  // it (the two partners of a handover meeting near their transition): no replanned move could keep
  // out, so the handover is resampled instead (above), as the paper's transitions are.
  const auto& region = schedule.region;
  if (region && !motion_.fixedEndsEnter(motions, region->robot, region->step, region->boxes)) {
    f.constraint.histories = {lazy::historyOf(layer.plan, region->robot, region->step)};
    f.constraint.histories.front().q = region->q;  // lifted when another transition sample is drawn
    if (region->other >= 0) f.constraint.histories.push_back(lazy::historyOf(layer.plan, region->other, region->other_step));
    f.constraint.region = region->boxes;
    f.constraint.object = region->object;
    f.constraint.t_begin = region->t_begin;
    f.constraint.t_end = region->t_end;
  }
  return failed(std::move(f));
}

MotionRound LazyDashRun::validate(const TaskLayerResult& layer, ScheduleResult& schedule) {
  MotionRound round;
  round.plan = std::move(schedule.plan);
  round.plan.planner = planner_name_;
  ValidationReport report;
  {
    log::PhaseTimer timer(emitter_, log::Phase::Validation);
    report = validatePlan(scene_, round.plan,
                          {.threads = params_.validation_threads, .stop = [this] { return deadline_.expired(); }});
  }
  if (report.stopped) return stopped(timeoutOutcome(deadline_), "validation: timeout");
  if (report.valid()) {
    round.kind = MotionRound::Kind::kSolved;
    return round;
  }
  // A plan that fails validation is never a result. A contact between the instants the scheduler's
  // continuous check sampled is a conflict like any other; anything else is a bug in the planner.
  const ValidationProblem& problem = report.problems.front();
  int step = -1;
  if (isContact(problem) && schedule.step_times.size() == layer.plan.steps.size())
    for (const std::string& id : {problem.robot, problem.other})
      if (const int r = robotIndex(scene_, id); r >= 0 && step < 0)
        step = stepOfRobotAt(layer.plan, schedule.step_times, r, problem.t);
  if (step < 0) return stopped(PlanOutcome::kInfeasible, "internal error: the planned schedule failed validation: " + problem.message);
  MotionFailure f;
  f.where = MotionFailure::Where::kValidation;
  f.step = step;
  f.constraint.cause = "validation: " + problem.message;
  for (const std::string& id : {problem.robot, problem.other})
    if (const int r = robotIndex(scene_, id); r >= 0) f.constraint.histories.push_back(lazy::historyOf(layer.plan, r, step));
  f.constraint.t_begin = problem.t;
  f.constraint.t_end = std::max(problem.t, problem.t_end);
  return failed(std::move(f));
}

void LazyDashRun::learn(const lazy::MotionConstraint& c) {
  const std::uint32_t id = motion_constraints_.add(c);
  emitter_.constraint(log::ConstraintKind::Motion, log::ConstraintAction::Created, id, c.describe(scene_), {}, c.cause);
}

void LazyDashRun::liftMotionConstraints(const std::vector<std::size_t>& ids, const std::string& why) {
  for (std::size_t id : ids)
    emitter_.constraint(log::ConstraintKind::Motion, log::ConstraintAction::Lifted, static_cast<std::uint32_t>(id),
                        motion_constraints_.all()[id].describe(scene_), {}, why);
}

// The one feedback function (Algorithm 1, lines 10-15). While the task plan's motion budget lasts, a
// failure becomes a motion constraint and the motion loop goes on with the same task plan (true): a
// region of the workspace makes the motion query and conflict resolution replan that history's move
// around it; transition configurations make task conflict detection sample others for the same plan; a
// time window makes conflict resolution check those instants. A failure with no region to learn (the
// way home) makes the roadmaps search harder instead. Otherwise it becomes a task constraint for the
// task query (false). nullopt: nothing more can be done on this attempt.
std::optional<bool> LazyDashRun::feedback(const MotionFailure& f, TaskLayerResult& layer,
                                          std::optional<MotionLayerResult>& motions, int motion_round) {
  if (f.where == MotionFailure::Where::kValidation) return validationFeedback(f, layer);
  if (f.step < 0) {  // no way home: no task hyperarc to blame
    if (!params_.budget_growth || home_budget_growths_++ >= kMaxHomeBudgetGrowths) return std::nullopt;
    motion_.scaleBudget(kBudgetGrowth);
    return true;
  }
  // The motion query found no way around the regions of the failed history: they did not help, and
  // kept in force they would fail that history again whenever a later task plan returns to it.
  if (f.where == MotionFailure::Where::kMotionQuery && !f.constraint.configurations.empty())
    liftMotionConstraints(motion_constraints_.liftRegionsFor(layer.plan, f.constraint.configurations.front().first,
                                                             f.step, f.constraint.configurations.front().second),
                          "the motion query found no way around it");
  const bool budget_left = motion_round + 1 < params_.motion_budget;
  // A region already learned for this history did not help: the next feedback applies.
  if (budget_left && !f.constraint.region.empty() && !motion_constraints_.contains(f.constraint)) {
    learn(f.constraint);
    emitter_.counter("region_replans", ++region_replans_);
    // The constrained move may lie before the failed step in the schedule: schedule again from the
    // conflict's time, with that history's move replanned around the region.
    scheduler_.forgetFrom(std::max(0.0, f.constraint.t_begin - params_.scheduler.delay_step));
    motions.reset();
    return true;
  }
  const TaskStep& step = layer.plan.steps[f.step];
  int& resamples = transition_resamples_[step.arc.value()];
  if (budget_left && f.resampleable && resamples < params_.max_transition_resamples) {
    bool rejected = false;
    for (const auto& [robot, q] : f.constraint.configurations) rejected = task_.rejectTransition(robot, q) || rejected;
    if (rejected) {
      ++resamples;
      learn(f.constraint);
      if (auto transitions = task_.resampleTransitions(layer.plan, deadline_)) {
        layer.transitions = std::move(*transitions);
        motions.reset();
        return true;
      }
    }
  }
  task_.addConstraint(motionFeedback(layer.plan, f.step, f.constraint.cause));
  return false;
}

std::optional<bool> LazyDashRun::validationFeedback(const MotionFailure& f, TaskLayerResult& layer) {
  if (plan_rechecks_ < params_.validator_rechecks) {
    ++plan_rechecks_;
    learn(f.constraint);
    scheduler_.alsoCheckAt(f.constraint.t_begin);
    if (f.constraint.t_end > f.constraint.t_begin) scheduler_.alsoCheckAt(f.constraint.t_end);
    scheduler_.forgetFrom(f.constraint.t_begin);
    emitter_.counter("validation_rechecks", ++rechecks_);
    return true;
  }
  if (validation_feedbacks_++ >= params_.validation_feedbacks) return std::nullopt;
  emitter_.counter("validation_feedbacks", validation_feedbacks_);
  scheduler_.forgetFrom(f.constraint.t_begin);
  task_.addConstraint(motionFeedback(layer.plan, f.step, f.constraint.cause));
  return false;
}

// Nothing left to try on this attempt (the task query has no plan under its constraints, the feedback
// loop has spent its allowances, or max_task_plans task plans failed). A sampling-based planner cannot
// prove a problem infeasible, and every generated scene is feasible: start again with no task
// constraints, fresh samples and (the first few times) larger roadmap budgets. H_T, H_M and the roadmaps
// are kept. False when restarts are off or the deadline has passed.
bool LazyDashRun::restart(const std::string& why) {
  if (!params_.restart_when_exhausted || deadline_.expired()) return false;
  task_.restart("restart after: " + why);
  // New samples lift the motion constraints too (paper, "Theoretical Properties").
  // Each lifted event names the constraint it lifts, as the task constraints' do.
  liftMotionConstraints(motion_constraints_.liftAll(), "restart after: " + why);
  last_restart_ = why;
  emitter_.counter("restarts", task_.restarts());
  if (params_.budget_growth && task_.restarts() <= kMaxRestartGrowths) motion_.scaleBudget(kBudgetGrowth);
  validation_feedbacks_ = 0;
  home_budget_growths_ = 0;
  budget_growths_ = 0;
  task_plans_ = 0;
  transition_resamples_.clear();
  return true;
}

void LazyDashRun::fillMotionStats() {
  PlanStats& stats = result_.stats;
  stats.sizes.motion_vertices = motion_.motionVertices();
  stats.sizes.motion_hyperarcs = motion_.motionHyperarcs();
  stats.sizes.motion_extended_vertices = motion_.extendedVertices();
  stats.sizes.motion_extended_hyperarcs = motion_.extendedHyperarcs();
  stats.roadmap_vertices = static_cast<std::int64_t>(motion_.roadmapVertices());
  stats.roadmap_edges = static_cast<std::int64_t>(motion_.roadmapEdges());
  stats.roadmaps.clear();
  for (int r = 0; r < world_.robotCount(); ++r)
    for (const bool holding : {false, true}) {
      const RoadmapSize size{scene_.robots[r].id + (holding ? "/holding" : "/empty"),
                             static_cast<std::int64_t>(motion_.roadmapVertices(r, holding)),
                             static_cast<std::int64_t>(motion_.roadmapEdges(r, holding))};
      if (size.vertices == 0) continue;
      emitter_.counter("roadmap_vertices:" + size.space, size.vertices);
      emitter_.counter("roadmap_edges:" + size.space, size.edges);
      stats.roadmaps.push_back(size);
    }
  emitter_.counter("motion_hyperarcs_coupled", static_cast<std::int64_t>(motion_.hypergraph().coupledHyperarcCount()));
}

PlanResult LazyDashRun::finish(PlanOutcome outcome, std::string message) {
  PlanStats& stats = result_.stats;
  const TaskLayerSizes s = task_.sizes();
  stats.sizes.task_vertices = s.task_vertices;
  stats.sizes.task_hyperarcs = s.task_hyperarcs;
  stats.sizes.task_extended_vertices = s.task_extended_vertices;
  stats.sizes.task_extended_hyperarcs = s.task_extended_hyperarcs;
  stats.task_constraints = static_cast<std::int64_t>(task_.constraints().size());
  int expansions = 0;
  for (int o = 0; o < task_.space().objectCount(); ++o) expansions += task_.space().extraLocationCount(o);
  stats.task_space_expansions = expansions;
  stats.iterations = task_.queries();
  fillMotionStats();
  stats.collision_checks_lazy = static_cast<std::int64_t>(context_.counters().configuration_checks);
  stats.motion_constraints = static_cast<std::int64_t>(motion_constraints_.size());
  stats.phase_seconds = emitter_.phaseTotals();
  stats.wall_seconds = emitter_.now();
  result_.outcome = outcome;
  result_.message = std::move(message);
  // A run that did not solve says what its restarts were for (the lifts log it only when there were
  // constraints to lift).
  if (outcome != PlanOutcome::kSolved && task_.restarts() > 0)
    result_.message += " (after " + std::to_string(task_.restarts()) + " restarts; the last after: " + last_restart_ + ")";
  emitter_.counter("collision_checks_lazy", stats.collision_checks_lazy);
  return result_;
}

PlanResult LazyDashRun::giveUp(std::string why) {
  return finish(deadline_.expired() ? timeoutOutcome(deadline_) : PlanOutcome::kInfeasible, std::move(why));
}

}  // namespace dash
