#include "engine/planners/lazy_dash.h"

#include <algorithm>
#include <cstdlib>
#include <initializer_list>
#include <unordered_map>
#include <utility>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/conflict/scheduler.h"
#include "engine/motion/motion_layer.h"
#include "engine/plan/plan_validator.h"
#include "engine/task/task_layer.h"

namespace dash {

namespace {

void applyTestFault(const PlannerSettings& settings, const Deadline& deadline) {
  if (settings.test_fault == "abort") std::abort();
  if (settings.test_fault == "ignore-deadline") {
    volatile std::uint64_t spin = 0;
    for (;;) spin = spin + 1;  // never returns: the batch runner must kill it from outside
  }
  (void)deadline;
}

PlanOutcome outcomeOf(TaskLayerStatus status, const Deadline& deadline) {
  if (status == TaskLayerStatus::kFeasible) return PlanOutcome::kSolved;
  if (status == TaskLayerStatus::kTimeout) return deadline.stopRequested() ? PlanOutcome::kCancelled : PlanOutcome::kTimeout;
  return PlanOutcome::kInfeasible;
}

void fillTaskStats(const TaskLayer& task, PlanStats& stats) {
  const TaskLayerSizes s = task.sizes();
  stats.sizes.task_vertices = s.task_vertices;
  stats.sizes.task_hyperarcs = s.task_hyperarcs;
  stats.sizes.task_extended_vertices = s.task_extended_vertices;
  stats.sizes.task_extended_hyperarcs = s.task_extended_hyperarcs;
  stats.task_constraints = static_cast<std::int64_t>(task.constraints().size());
  int expansions = 0;
  for (int o = 0; o < task.space().objectCount(); ++o) expansions += task.space().extraLocationCount(o);
  stats.task_space_expansions = expansions;
  stats.iterations = task.queries();
}

}  // namespace

namespace {

constexpr int kMaxMotionRounds = 200;
constexpr double kBudgetGrowthAfterLift = 4.0;
constexpr int kMaxHomeBudgetGrowths = 3;
constexpr int kMaxBudgetGrowths = 3;  // after lifted motion bans: at most 64x the first budget
constexpr int kMaxValidationFeedbacks = 5;
constexpr int kMaxRechecksPerRound = 3;

/// A collision between robots, held objects or resting objects (what conflict resolution checks).
bool isContact(const ValidationProblem& problem) {
  return problem.kind == ProblemKind::kRobotRobotCollision || problem.kind == ProblemKind::kHeldObjectCollision ||
         problem.kind == ProblemKind::kRobotObjectCollision;
}

/// The task step a collision found by the validator belongs to: the first transition at or after it
/// of one of the robots involved (the move into it is where the contact was), else the last before it.
/// -1 when the problem is not a collision between robots or held objects.
int missedConflictStep(const Scene& scene, const TaskPlan& plan, const std::vector<double>& step_times,
                       const ValidationProblem& problem) {
  if (!isContact(problem)) return -1;
  if (step_times.size() != plan.steps.size()) return -1;
  std::vector<int> robots;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r)
    if (scene.robots[r].id == problem.robot || scene.robots[r].id == problem.other) robots.push_back(r);
  auto involves = [&](const TaskArc& a) {
    return std::find(robots.begin(), robots.end(), a.robot) != robots.end() ||
           std::find(robots.begin(), robots.end(), a.robot2) != robots.end();
  };
  int after = -1, before = -1;
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    if (!involves(plan.steps[k].action)) continue;
    if (step_times[k] >= problem.t && (after < 0 || step_times[k] < step_times[after])) after = k;
    if (step_times[k] < problem.t && (before < 0 || step_times[k] > step_times[before])) before = k;
  }
  return after >= 0 ? after : before;
}

double pathLength(const Plan& plan) {
  double total = 0.0;
  for (const RobotTrajectory& r : plan.robots)
    for (std::size_t i = 1; i < r.points.size(); ++i) total += (r.points[i].q - r.points[i - 1].q).norm();
  return total;
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

PlanResult LazyDash::solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                           log::EventSink* sink) {
  applyTestFault(settings, deadline);
  seedOmplOnce(settings.seed);
  log::EventEmitter emitter(sink);
  const CollisionWorld world(scene, {.clearance = params_.clearance});
  CollisionContext context(world);
  TaskLayer task(scene, world, context, emitter, settings.seed);
  MotionLayer motion(world, context, emitter, params_.motion);
  Scheduler scheduler(world, context);
  PlanResult result;
  auto finish = [&](PlanOutcome outcome, std::string message) {
    fillTaskStats(task, result.stats);
    result.stats.sizes.motion_vertices = motion.motionVertices();
    result.stats.sizes.motion_hyperarcs = motion.motionHyperarcs();
    result.stats.sizes.motion_extended_vertices = motion.extendedVertices();
    result.stats.sizes.motion_extended_hyperarcs = motion.extendedHyperarcs();
    result.stats.roadmap_vertices = static_cast<std::int64_t>(motion.roadmapVertices());
    result.stats.roadmap_edges = static_cast<std::int64_t>(motion.roadmapEdges());
    result.stats.collision_checks_lazy = static_cast<std::int64_t>(context.counters().configuration_checks);
    result.stats.phase_seconds = emitter.phaseTotals();
    result.outcome = outcome;
    result.message = std::move(message);
    emitter.counter("collision_checks_lazy", result.stats.collision_checks_lazy);
    return result;
  };

  int home_budget_growths = 0;
  int validation_feedbacks = 0;
  int budget_growths = 0;
  std::unordered_map<std::uint32_t, int> transition_resamples;  // per task hyperarc
  // Other configurations for a step's transition instead of a ban on its hyperarc (at most
  // max_transition_resamples per hyperarc): true when one of `configs` is newly rejected.
  auto resampleTransition = [&](const TaskStep& step, std::initializer_list<std::pair<int, const JointVector*>> configs,
                                const std::string& why) {
    int& resamples = transition_resamples[step.arc.value()];
    if (resamples >= params_.max_transition_resamples) return false;
    bool rejected = false;
    for (const auto& [robot, q] : configs) rejected = task.rejectTransition(robot, *q, why) || rejected;
    if (rejected) ++resamples;
    return rejected;
  };
  std::int64_t reused_steps = 0;  // steps conflict resolution took from the previous round's schedule
  std::int64_t rechecks = 0;      // schedules built again after the validator found a contact
  for (int round = 0; round < kMaxMotionRounds; ++round) {
    const TaskLayerResult layer = task.plan(deadline);
    if (layer.status != TaskLayerStatus::kFeasible)
      return finish(outcomeOf(layer.status, deadline),
                    "task layer: " + std::string(toString(layer.status)) + (layer.reason.empty() ? "" : " (" + layer.reason + ")"));
    // No schedule avoids the hyperarcs the motion layer failed on: search harder on the same ones.
    if (layer.motion_bans_lifted && budget_growths < kMaxBudgetGrowths) {
      ++budget_growths;
      motion.scaleBudget(kBudgetGrowthAfterLift);
    }
    if (settings.task_only) {
      result.task_plan_json = layer.plan.toJson(task.space());
      return finish(PlanOutcome::kSolved, layer.plan.describe(task.space()));
    }
    // The motion layer times its own construction (H_M's anchors) and query (moves, roadmap growth).
    MotionLayerResult motions = motion.plan(layer.plan, layer.transitions, task.space(), deadline);
    if (motions.status == MotionStatus::kTimeout) return finish(outcomeOf(TaskLayerStatus::kTimeout, deadline), "motion layer: timeout");
    if (motions.status == MotionStatus::kFailed) {
      if (motions.failed_step < 0) {
        // No way home: no task hyperarc to blame; the roadmaps search harder (a bounded number of times).
        if (home_budget_growths++ < kMaxHomeBudgetGrowths) {
          motion.scaleBudget(kBudgetGrowthAfterLift);
          emitter.setIteration(emitter.iteration() + 1);
          continue;
        }
        return finish(PlanOutcome::kInfeasible, "motion layer: " + motions.reason);
      }
      // Both ends were free but the roadmap found no way: first another configuration for the same
      // transition (task conflict detection samples again), then a ban on the hyperarc.
      if (motions.ends_free && resampleTransition(layer.plan.steps[motions.failed_step],
                                                  {{motions.failed_robot, &motions.failed_q}},
                                                  "motion query: " + motions.reason)) {
        emitter.setIteration(emitter.iteration() + 1);
        continue;
      }
      task.addConstraint(motionFeedback(layer.plan, motions.failed_step, "motion query: " + motions.reason));
      emitter.setIteration(emitter.iteration() + 1);
      continue;
    }
    // A plan that fails validation is never a result. A contact the validator finds between the instants
    // the scheduler's continuous check sampled (same resolution, other instants): the scheduler checks
    // that instant too from now on and schedules again from there, the same task plan and the steps
    // before it kept (a few times per round; then it goes back to the task query like any conflict).
    ScheduleResult schedule;
    Plan plan;
    ValidationReport report;
    for (int recheck = 0;; ++recheck) {
      {
        log::PhaseTimer timer(emitter, log::Phase::ConflictResolution);
        const MoveReplanner replan = [&](int r, const JointVector& from, const JointVector& to,
                                         const MotionContext& ctx) { return motion.connect(r, from, to, ctx, deadline); };
        schedule = scheduler.build(layer.plan, layer.transitions, motions, task.space(), replan, deadline);
      }
      reused_steps += schedule.stats.reused_steps;
      emitter.counter("scheduled_steps_reused", reused_steps);
      if (!schedule.ok) break;
      plan = std::move(schedule.plan);
      plan.planner = name();
      report = validatePlan(scene, plan);
      if (report.valid() || recheck >= kMaxRechecksPerRound || !isContact(report.problems.front())) break;
      const ValidationProblem& contact = report.problems.front();
      scheduler.alsoCheckAt(contact.t);
      if (contact.t_end > contact.t) scheduler.alsoCheckAt(contact.t_end);
      scheduler.forgetFrom(contact.t);
      emitter.counter("validation_rechecks", ++rechecks);
    }
    if (!schedule.ok) {
      if (deadline.expired()) return finish(outcomeOf(TaskLayerStatus::kTimeout, deadline), "conflict resolution: timeout");
      if (schedule.failed_step < 0) return finish(PlanOutcome::kInfeasible, "conflict resolution: " + schedule.reason);
      // A handover that cannot be scheduled: first another handover configuration (pose, IK branches)
      // for the same task plan, then a ban on the hyperarc.
      const TaskStep& failed = layer.plan.steps[schedule.failed_step];
      const TransitionConfig& tc = layer.transitions[schedule.failed_step];
      if (failed.action.type == TaskArcType::kHandover &&
          resampleTransition(failed, {{failed.action.robot, &tc.q}, {failed.action.robot2, &tc.q2}},
                             "conflict resolution: " + schedule.reason)) {
        emitter.setIteration(emitter.iteration() + 1);
        continue;
      }
      task.addConstraint(motionFeedback(layer.plan, schedule.failed_step, "conflict resolution: " + schedule.reason));
      emitter.setIteration(emitter.iteration() + 1);
      continue;
    }
    if (!report.valid()) {
      // Still a contact after the rechecks: back to the task query like any conflict, a few times per
      // run; anything else is a bug in the planner.
      const int step = missedConflictStep(scene, layer.plan, schedule.step_times, report.problems.front());
      if (step < 0 || validation_feedbacks++ >= kMaxValidationFeedbacks)
        return finish(PlanOutcome::kInfeasible, "internal error: the planned schedule failed validation: " +
                                                    report.problems.front().message);
      emitter.counter("validation_feedbacks", validation_feedbacks);
      scheduler.forgetFrom(report.problems.front().t);
      task.addConstraint(motionFeedback(layer.plan, step, "validation: " + report.problems.front().message));
      emitter.setIteration(emitter.iteration() + 1);
      continue;
    }
    result.stats.makespan = plan.makespan;
    result.stats.path_length = pathLength(plan);
    result.plan = std::move(plan);
    return finish(PlanOutcome::kSolved, "solved");
  }
  return finish(PlanOutcome::kInfeasible, "gave up after " + std::to_string(kMaxMotionRounds) + " motion rounds");
}

}  // namespace dash
