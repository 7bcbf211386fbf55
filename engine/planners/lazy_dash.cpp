#include "engine/planners/lazy_dash.h"

#include <algorithm>
#include <cstdlib>
#include <initializer_list>
#include <optional>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/conflict/scheduler.h"
#include "engine/motion/motion_constraints.h"
#include "engine/motion/motion_layer.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/plan/plan_validator.h"
#include "engine/task/task_layer.h"

namespace dash {

namespace {

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

constexpr int kMaxTaskRounds = 200;  // task plans tried at most (Algorithm 1's outer loop)
constexpr double kBudgetGrowth = 4.0;
constexpr int kMaxHomeBudgetGrowths = 3;
constexpr int kMaxBudgetGrowths = 3;  // after lifted motion bans: at most 64x the first budget
constexpr int kMaxRestartGrowths = 3;  // restarts that also grow the roadmap budgets

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

void applyParameters(LazyDashParams& p, const ParamValues& v) {
  auto set = [&](const char* name, auto& field) {
    if (!v.contains(name)) return;
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>) field = paramBool(v, name);
    else field = static_cast<T>(paramInt(v, name));
  };
  set("straight_first", p.motion.straight_first);
  set("global_sampling", p.motion.global_sampling);
  set("path_simplification", p.motion.roadmap.simplify);
  set("keep_tree_paths", p.motion.roadmap.keep_tree_paths);
  set("roadmap_query_samples", p.motion.roadmap.query_samples);
  set("roadmap_max_vertices", p.motion.roadmap.max_vertices);
  if (v.contains("deep_backoffs") && !paramBool(v, "deep_backoffs")) p.motion.deep_approach_distances.clear();
  set("round_trip_removal", p.task.query.remove_round_trips);
  set("approach_line_preference", p.task.conflicts.prefer_free_approach);
  set("handover_class_bans", p.task.handover_class_bans);
  set("transition_resamples", p.max_transition_resamples);
  set("budget_growth", p.budget_growth);
  set("validator_rechecks", p.validator_rechecks);
  set("validation_feedbacks", p.validation_feedbacks);
  set("validation_threads", p.validation_threads);
  set("motion_budget", p.motion_budget);
  set("restart_when_exhausted", p.restart_when_exhausted);
  if (v.contains("clearance")) p.clearance = paramReal(v, "clearance");
  applySchedulerParameters(p.scheduler, v);
}

namespace {

/// Algorithm 1's one failure type: where a motion round on a task plan stopped, and what it learned as
/// a motion constraint (the histories in conflict and the region).
struct MotionFailure {
  enum class Where { kMotionQuery, kConflictResolution, kValidation };
  Where where = Where::kMotionQuery;
  int step = -1;                // the task step it belongs to; -1: none (the way home)
  MotionConstraint constraint;  // C_M
  /// The region is transition configurations, and others for the same transitions may do.
  bool resampleable = false;
};

/// One motion round (Algorithm 1, lines 9-13): solved, failed (with what it learned), or stopped
/// (out of time, or a failure nothing can be learned from).
struct MotionRound {
  enum class Kind { kSolved, kFailed, kStopped };
  Kind kind = Kind::kFailed;
  MotionFailure failure;  // kFailed
  PlanOutcome outcome = PlanOutcome::kInfeasible;  // kStopped
  std::string message;                             // kStopped
  Plan plan;                                       // kSolved
};

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

}  // namespace

PlanResult LazyDash::solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                           log::EventSink* sink) {
  applyTestFault(settings);
  // Named parameters: checked (InputError naming a bad one), then applied over the constructor's.
  const ParamValues effective = resolveParameters(name(), settings.params);
  LazyDashParams params = params_;
  ParamValues overrides;
  for (const auto& [key, value] : settings.params) overrides[key] = effective.at(key);
  applyParameters(params, overrides);
  const OmplSeedScope ompl_seeds(settings.seed);
  log::EventEmitter emitter(sink);
  log::PhaseTimer setup(emitter, log::Phase::Other);
  const CollisionWorld world(scene, {.clearance = params.clearance});
  CollisionContext context(world);
  TaskLayer task(scene, world, context, emitter, settings.seed, params.task);
  MotionLayer motion(world, context, emitter, params.motion);
  Scheduler scheduler(world, context, params.scheduler);
  scheduler.reportProgress(&emitter);  // steps scheduled, for people watching (reporting only)
  setup.stop();
  MotionConstraintSet motion_constraints;
  PlanResult result;
  std::string last_restart;  // why the last restart happened
  auto finish = [&](PlanOutcome outcome, std::string message) {
    fillTaskStats(task, result.stats);
    result.stats.sizes.motion_vertices = motion.motionVertices();
    result.stats.sizes.motion_hyperarcs = motion.motionHyperarcs();
    result.stats.sizes.motion_extended_vertices = motion.extendedVertices();
    result.stats.sizes.motion_extended_hyperarcs = motion.extendedHyperarcs();
    result.stats.roadmap_vertices = static_cast<std::int64_t>(motion.roadmapVertices());
    result.stats.roadmap_edges = static_cast<std::int64_t>(motion.roadmapEdges());
    result.stats.collision_checks_lazy = static_cast<std::int64_t>(context.counters().configuration_checks);
    result.stats.motion_constraints = static_cast<std::int64_t>(motion_constraints.size());
    result.stats.phase_seconds = emitter.phaseTotals();
    result.stats.wall_seconds = emitter.now();
    result.stats.roadmaps.clear();
    for (int r = 0; r < world.robotCount(); ++r)
      for (const bool holding : {false, true}) {
        const RoadmapSize size{scene.robots[r].id + (holding ? "/holding" : "/empty"),
                               static_cast<std::int64_t>(motion.roadmapVertices(r, holding)),
                               static_cast<std::int64_t>(motion.roadmapEdges(r, holding))};
        if (size.vertices == 0) continue;
        emitter.counter("roadmap_vertices:" + size.space, size.vertices);
        emitter.counter("roadmap_edges:" + size.space, size.edges);
        result.stats.roadmaps.push_back(size);
      }
    emitter.counter("motion_hyperarcs_coupled", static_cast<std::int64_t>(motion.hypergraph().coupledHyperarcCount()));
    result.outcome = outcome;
    result.message = std::move(message);
    // A run that did not solve says what its restarts were for (the lifts log it only when there were
    // constraints to lift).
    if (outcome != PlanOutcome::kSolved && task.restarts() > 0)
      result.message += " (after " + std::to_string(task.restarts()) + " restarts; the last after: " + last_restart + ")";
    emitter.counter("collision_checks_lazy", result.stats.collision_checks_lazy);
    return result;
  };

  int home_budget_growths = 0;
  int validation_feedbacks = 0;
  int budget_growths = 0;
  int task_plans = 0;  // task plans of this attempt (Algorithm 1's outer loop), at most kMaxTaskRounds
  std::unordered_map<std::uint32_t, int> transition_resamples;  // per task hyperarc
  std::int64_t reused_steps = 0;  // steps conflict resolution took from the previous round's schedule
  std::int64_t rechecks = 0;      // schedules built again after the validator found a contact
  auto nextIteration = [&] { emitter.setIteration(emitter.iteration() + 1); };
  // Nothing left to try on this attempt (the task query has no plan under its constraints, the
  // feedback loop has spent its allowances, or kMaxTaskRounds task plans failed). A sampling-based
  // planner cannot prove a problem infeasible, and every generated scene is feasible: start again with
  // no task constraints, fresh samples and (the first few times) larger roadmap budgets. H_T, H_M and
  // the roadmaps are kept. False when restarts are off (the paper) or the deadline has passed.
  auto restart = [&](const std::string& why) {
    if (!params.restart_when_exhausted || deadline.expired()) return false;
    task.restart("restart after: " + why);
    last_restart = why;
    emitter.counter("restarts", task.restarts());
    if (params.budget_growth && task.restarts() <= kMaxRestartGrowths) motion.scaleBudget(kBudgetGrowth);
    validation_feedbacks = 0;
    home_budget_growths = 0;
    budget_growths = 0;
    task_plans = 0;
    transition_resamples.clear();
    return true;
  };

  // Lines 9-13 of Algorithm 1 on one task plan: the motion hypergraph and the motion query (MotionLayer:
  // H_M, the optimistic schedule), motion conflict resolution (Scheduler), and the validator. `motions`
  // is kept between rounds whose transitions did not change (a validator contact only reschedules).
  auto motionRound = [&](const TaskLayerResult& layer, std::optional<MotionLayerResult>& motions) -> MotionRound {
    if (!motions) motions = motion.plan(layer.plan, layer.transitions, task.space(), deadline);
    if (motions->status == MotionStatus::kTimeout) return stopped(outcomeOf(TaskLayerStatus::kTimeout, deadline), "motion layer: timeout");
    if (motions->status == MotionStatus::kFailed) {
      MotionFailure f;
      f.where = MotionFailure::Where::kMotionQuery;
      f.step = motions->failed_step;
      f.constraint.cause = "motion query: " + motions->reason;
      if (f.step >= 0) {
        f.constraint.histories = {{motions->failed_robot, f.step}};
        f.constraint.configurations = {{motions->failed_robot, motions->failed_q}};
        f.resampleable = motions->ends_free;
      }
      motions.reset();
      return failed(std::move(f));
    }
    ScheduleResult schedule;
    {
      log::PhaseTimer timer(emitter, log::Phase::ConflictResolution);
      const MoveReplanner replan = [&](int r, const JointVector& from, const JointVector& to, const MotionContext& ctx) {
        return motion.connect(r, from, to, ctx, deadline);
      };
      schedule = scheduler.build(layer.plan, layer.transitions, *motions, task.space(), replan, deadline);
    }
    reused_steps += schedule.stats.reused_steps;
    emitter.counter("scheduled_steps_reused", reused_steps);
    if (!schedule.ok) {
      if (deadline.expired()) return stopped(outcomeOf(TaskLayerStatus::kTimeout, deadline), "conflict resolution: timeout");
      if (schedule.failed_step < 0) return stopped(PlanOutcome::kInfeasible, "conflict resolution: " + schedule.reason);
      MotionFailure f;
      f.where = MotionFailure::Where::kConflictResolution;
      f.step = schedule.failed_step;
      f.constraint.cause = "conflict resolution: " + schedule.reason;
      const TaskArc& a = layer.plan.steps[f.step].action;
      const TransitionConfig& tc = layer.transitions[f.step];
      f.constraint.histories = {{a.robot, f.step}};
      f.constraint.configurations = {{a.robot, tc.q}};
      if (a.type == TaskArcType::kHandover) {
        f.constraint.histories.push_back({a.robot2, f.step});
        f.constraint.configurations.push_back({a.robot2, tc.q2});
        f.resampleable = true;  // another handover configuration (pose, IK branches)
      }
      return failed(std::move(f));
    }
    MotionRound round;
    round.plan = std::move(schedule.plan);
    round.plan.planner = name();
    ValidationReport report;
    {
      log::PhaseTimer timer(emitter, log::Phase::Validation);
      report = validatePlan(scene, round.plan, {.threads = params.validation_threads});
    }
    if (report.valid()) {
      round.kind = MotionRound::Kind::kSolved;
      return round;
    }
    // A plan that fails validation is never a result. A contact between the instants the scheduler's
    // continuous check sampled is a conflict like any other; anything else is a bug in the planner.
    const ValidationProblem& problem = report.problems.front();
    const int step = missedConflictStep(scene, layer.plan, schedule.step_times, problem);
    if (step < 0) return stopped(PlanOutcome::kInfeasible, "internal error: the planned schedule failed validation: " + problem.message);
    MotionFailure f;
    f.where = MotionFailure::Where::kValidation;
    f.step = step;
    f.constraint.cause = "validation: " + problem.message;
    for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r)
      if (scene.robots[r].id == problem.robot || scene.robots[r].id == problem.other) f.constraint.histories.push_back({r, step});
    f.constraint.t_begin = problem.t;
    f.constraint.t_end = std::max(problem.t, problem.t_end);
    return failed(std::move(f));
  };

  // The one feedback function (Algorithm 1, lines 10-15). While the task plan's motion budget lasts, a
  // failure becomes a motion constraint and the motion loop goes on with the same task plan (true): its
  // configuration region makes task conflict detection choose other transition configurations for the
  // same plan; its time region makes conflict resolution check those instants. A failure with no region
  // to learn (the way home) makes the roadmaps search harder instead. Otherwise it becomes a task
  // constraint for the task query (false). nullopt: nothing more can be done (infeasible).
  int plan_rechecks = 0;
  auto feedback = [&](const MotionFailure& f, TaskLayerResult& layer, std::optional<MotionLayerResult>& motions,
                      int motion_round) -> std::optional<bool> {
    auto learn = [&](const MotionConstraint& c) {
      const std::uint32_t id = motion_constraints.add(c);
      emitter.constraint(log::ConstraintKind::Motion, log::ConstraintAction::Created, id, c.describe(scene), {}, c.cause);
    };
    const bool budget_left = motion_round + 1 < params.motion_budget;
    if (f.where == MotionFailure::Where::kValidation) {
      if (plan_rechecks < params.validator_rechecks) {
        ++plan_rechecks;
        learn(f.constraint);
        scheduler.alsoCheckAt(f.constraint.t_begin);
        if (f.constraint.t_end > f.constraint.t_begin) scheduler.alsoCheckAt(f.constraint.t_end);
        scheduler.forgetFrom(f.constraint.t_begin);
        emitter.counter("validation_rechecks", ++rechecks);
        return true;
      }
      if (validation_feedbacks++ >= params.validation_feedbacks) return std::nullopt;
      emitter.counter("validation_feedbacks", validation_feedbacks);
      scheduler.forgetFrom(f.constraint.t_begin);
      task.addConstraint(motionFeedback(layer.plan, f.step, f.constraint.cause));
      return false;
    }
    if (f.step < 0) {  // no way home: no task hyperarc to blame
      if (!params.budget_growth || home_budget_growths++ >= kMaxHomeBudgetGrowths) return std::nullopt;
      motion.scaleBudget(kBudgetGrowth);
      return true;
    }
    const TaskStep& step = layer.plan.steps[f.step];
    int& resamples = transition_resamples[step.arc.value()];
    if (budget_left && f.resampleable && resamples < params.max_transition_resamples) {
      bool rejected = false;
      for (const auto& [robot, q] : f.constraint.configurations) rejected = task.rejectTransition(robot, q) || rejected;
      if (rejected) {
        ++resamples;
        learn(f.constraint);
        if (auto transitions = task.resampleTransitions(layer.plan, deadline)) {
          layer.transitions = std::move(*transitions);
          motions.reset();
          return true;
        }
      }
    }
    task.addConstraint(motionFeedback(layer.plan, f.step, f.constraint.cause));
    return false;
  };

  // Restarts off (the paper) or the deadline passed: the run ends here.
  auto giveUp = [&](std::string why) {
    return finish(deadline.expired() ? outcomeOf(TaskLayerStatus::kTimeout, deadline) : PlanOutcome::kInfeasible,
                  std::move(why));
  };
  emitter.counter("restarts", 0);
  for (;;) {  // Algorithm 1, line 3
    if (task_plans == kMaxTaskRounds) {
      const std::string why = "gave up after " + std::to_string(kMaxTaskRounds) + " task plans";
      if (!restart(why)) return giveUp(why);
    }
    ++task_plans;
    TaskLayerResult layer = task.plan(deadline);  // lines 4-7
    if (layer.status != TaskLayerStatus::kFeasible) {
      const std::string why =
          "task layer: " + std::string(toString(layer.status)) + (layer.reason.empty() ? "" : " (" + layer.reason + ")");
      if (layer.status != TaskLayerStatus::kInfeasible) return finish(outcomeOf(layer.status, deadline), why);
      if (layer.no_route_in_task_hypergraph) return finish(PlanOutcome::kInfeasible, why);  // proven
      if (restart(why)) continue;
      return giveUp(why);
    }
    // No schedule avoids the hyperarcs the motion layer failed on: search harder on the same ones.
    if (layer.motion_bans_lifted && params.budget_growth && budget_growths < kMaxBudgetGrowths) {
      ++budget_growths;
      motion.scaleBudget(kBudgetGrowth);
    }
    if (settings.task_only) {
      result.task_plan_json = layer.plan.toJson(task.space());
      return finish(PlanOutcome::kSolved, layer.plan.describe(task.space()));
    }
    std::optional<MotionLayerResult> motions;
    plan_rechecks = 0;
    for (int motion_round = 0;; ++motion_round) {  // line 8: while S_T valid and S_M not valid
      MotionRound round = motionRound(layer, motions);
      if (round.kind == MotionRound::Kind::kSolved) {
        result.stats.makespan = round.plan.makespan;
        result.stats.path_length = round.plan.jointPathLength();
        result.plan = std::move(round.plan);
        return finish(PlanOutcome::kSolved, "solved");
      }
      if (round.kind == MotionRound::Kind::kStopped) {
        if (round.outcome != PlanOutcome::kInfeasible) return finish(round.outcome, std::move(round.message));
        if (restart(round.message)) break;
        return giveUp(std::move(round.message));
      }
      const std::optional<bool> stay = feedback(round.failure, layer, motions, motion_round);
      if (!stay) {
        const std::string why = round.failure.where == MotionFailure::Where::kValidation
                                    ? "internal error: the planned schedule failed validation: " + round.failure.constraint.cause
                                    : round.failure.constraint.cause;
        if (restart(why)) break;
        return giveUp(why);
      }
      nextIteration();
      if (!*stay) break;  // lines 14-15: a task constraint, back to the task query
    }
  }
}

}  // namespace dash
