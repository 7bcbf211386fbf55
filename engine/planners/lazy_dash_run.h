#pragma once
// One run of Lazy-DaSH, read beside the paper's Algorithm 1 (engine/planners/lazy_dash.h). Its methods
// are the algorithm's steps:
//   run()            lines 3-21: the outer loop over task plans, the inner loop over motion rounds;
//   taskPlan()       lines 4-7: H_T, the task query (H_TE) and task conflict detection (TaskLayer);
//   motionQuery()    lines 10-13: H_M for the task plan and the motion query (H_ME) along it (MotionLayer),
//                    respecting the motion constraints C_M of each history;
//   resolveConflicts() line 17: motion conflict resolution (Scheduler, Algorithm 3), respecting C_M;
//   validate()       the certified validator on the valid schedule (beyond the paper: a plan is never
//                    returned without it);
//   feedback()       lines 10-15: a failure becomes a motion constraint C_M while the task plan's motion
//                    budget lasts (the motion layer replans the history around its region on the same
//                    task plan), else a task constraint C_T for the next task query;
//   restart()        beyond the paper's loop, and named: restart_when_exhausted.
#include <cstdint>
#include <optional>
#include <string>
#include <unordered_map>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/conflict/scheduler.h"
#include "engine/motion/motion_constraints.h"
#include "engine/motion/motion_layer.h"
#include "engine/planners/lazy_dash.h"
#include "engine/task/task_layer.h"

namespace dash {

/// Where a motion round on a task plan stopped, and what it learned (the motion constraint C_M).
struct MotionFailure {
  enum class Where { kMotionQuery, kConflictResolution, kValidation };
  Where where = Where::kMotionQuery;
  int step = -1;                // the task step it belongs to; -1: none (the way home)
  lazy::MotionConstraint constraint;  // C_M
  /// The region is transition configurations, and others for the same transitions may do.
  bool resampleable = false;
};

/// One motion round (Algorithm 1, lines 10-17): solved, failed (with what it learned), or stopped
/// (out of time, or a failure nothing can be learned from).
struct MotionRound {
  enum class Kind { kSolved, kFailed, kStopped };
  Kind kind = Kind::kFailed;
  MotionFailure failure;                           // kFailed
  PlanOutcome outcome = PlanOutcome::kInfeasible;  // kStopped
  std::string message;                             // kStopped
  Plan plan;                                       // kSolved
};

class LazyDashRun {
 public:
  LazyDashRun(const Scene& scene, const LazyDashParams& params, const PlannerSettings& settings,
              const Deadline& deadline, log::EventEmitter& emitter, std::string planner_name);

  /// Algorithm 1 until solved, out of time, or (restarts off) out of options.
  PlanResult run();

 private:
  /// What the inner loop on one task plan ended with.
  enum class Inner { kNextTaskPlan, kRestarted };

  /// Lines 8-17 on one task plan: motion rounds until solved (result_ filled), or a task constraint
  /// sends the run back to the task query, or the attempt restarts. nullopt: the run is over (result_).
  std::optional<Inner> motionLoop(TaskLayerResult& layer);
  MotionRound motionRound(TaskLayerResult& layer, std::optional<MotionLayerResult>& motions);
  /// Lines 10-13: nullopt when the motion query found every move (in `motions`), else the round's end.
  std::optional<MotionRound> motionQuery(const TaskLayerResult& layer, std::optional<MotionLayerResult>& motions);
  /// Line 17, Algorithm 3.
  ScheduleResult resolveConflicts(const TaskLayerResult& layer, const MotionLayerResult& motions);
  /// Conflict resolution failed: C_M with the conflict's region when the constrained move can keep out
  /// of it (MotionLayer::fixedEndsEnter), else the failed step's transition configurations.
  MotionRound conflictFailure(const TaskLayerResult& layer, const MotionLayerResult& motions,
                              const ScheduleResult& schedule);
  MotionRound validate(const TaskLayerResult& layer, ScheduleResult& schedule);
  /// true: stay on the task plan (a motion constraint learned); false: a task constraint was added;
  /// nullopt: nothing more can be done on this attempt.
  std::optional<bool> feedback(const MotionFailure& f, TaskLayerResult& layer, std::optional<MotionLayerResult>& motions,
                               int motion_round);
  std::optional<bool> validationFeedback(const MotionFailure& f, TaskLayerResult& layer);
  void learn(const lazy::MotionConstraint& c);
  /// Logs the motion constraints `ids` (just lifted) as lifted, because of `why`.
  void liftMotionConstraints(const std::vector<std::size_t>& ids, const std::string& why);
  bool restart(const std::string& why);
  PlanResult finish(PlanOutcome outcome, std::string message);
  PlanResult giveUp(std::string why);
  void fillMotionStats();

  const Scene& scene_;
  LazyDashParams params_;
  const PlannerSettings& settings_;
  const Deadline& deadline_;
  log::EventEmitter& emitter_;
  std::string planner_name_;
  CollisionWorld world_;
  CollisionContext context_;
  TaskLayer task_;
  MotionLayer motion_;
  Scheduler scheduler_;
  lazy::MotionConstraintSet motion_constraints_;
  PlanResult result_;

  // Allowances of one attempt (restart() resets them).
  int task_plans_ = 0;            ///< task plans tried (Algorithm 1's outer loop), at most max_task_plans
  int home_budget_growths_ = 0;   ///< roadmap budget growths for a missing way home
  int validation_feedbacks_ = 0;  ///< validator contacts fed back as task constraints
  int budget_growths_ = 0;        ///< roadmap budget growths after lifted motion bans
  std::unordered_map<std::uint32_t, int> transition_resamples_;  ///< per task hyperarc
  int plan_rechecks_ = 0;         ///< validator rechecks on the current task plan
  // Counters of the run (reported as events).
  std::int64_t reused_steps_ = 0;  ///< steps conflict resolution took from the previous round's schedule
  std::int64_t rechecks_ = 0;      ///< schedules built again after the validator found a contact
  std::int64_t region_replans_ = 0;  ///< motion rounds replanned around a learned C_M region
  std::string last_restart_;       ///< why the last restart happened
};

}  // namespace dash
