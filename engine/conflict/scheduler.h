#pragma once
// Motion conflict resolution by scheduled adaptive robot coordination (paper, Algorithm 3), in the
// form this workbench uses: the task plan's dependency graph orders the transitions; each robot's
// motions from the optimistic schedule are placed in time one transition at a time, handovers
// synchronised (both robots at their handover configurations at the same instant), and every new
// timed piece is checked in continuous time against everything already scheduled (ScheduleChecker).
// A conflict is resolved first by retiming (a later departure: the robot waits where it stands, which
// is always clear), then by replanning the move in the space of the robot with the robots in its way
// standing still, then by replanning in the composite space of the robots in conflict (ARC's
// subproblem: the step's participants plus the robots standing in their way, which may step aside and
// come back; the robot set grows with each new robot found in the way). What cannot be resolved is
// reported, with the step it happened at, for the planner to turn into a constraint. A build whose
// task plan starts with the same steps as the last build's takes those steps as they were scheduled
// then (ScheduleMemo) and goes on from the first step where the plans part.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "engine/conflict/composite_planner.h"
#include "engine/conflict/conflict_region.h"
#include "engine/conflict/schedule_checker.h"
#include "engine/conflict/schedule_memo.h"
#include "engine/core/deadline.h"
#include "engine/core/planner_params.h"
#include "engine/events/event_emitter.h"
#include "engine/motion/motion_constraints.h"
#include "engine/motion/motion_layer.h"
#include "engine/plan/plan.h"

namespace dash {

struct ScheduleBuild;

struct SchedulerParams {
  double velocity_scale = 0.5;    ///< fraction of each joint's velocity_max used for motions
  double dwell = 0.1;             ///< seconds a gripper needs to close or open
  double delay_step = 0.25;       ///< retiming granularity, seconds
  double max_delay = 30.0;        ///< give up retiming a transition after this much delay
  double min_segment = 0.02;      ///< shortest segment duration, seconds
  int max_composite_robots = 4;   ///< ARC's robot set stops growing here
  int composite_attempts = 3;     ///< composite replans per step
  std::size_t composite_iterations = 5000; ///< work budget of one composite replan (RRT-Connect iterations)
  // Beyond the paper (named planner parameters, engine/core/planner_params.h):
  bool staggered_arrivals = true;  ///< handover arrival modes 1 and 2 (one robot in place first)
  bool idle_arms_home = true;      ///< an idle robot in the way is sent home
  bool parking = true;             ///< robots stepping aside go to a parking configuration, else home
  bool schedule_memo = true;       ///< resume from the last schedule's shared leading steps
  /// The repairs that replan motions (around the partner or a standing robot, sending an idle robot
  /// home, ARC's composite subproblem); off: conflict resolution only retimes (an ablation).
  bool conflict_replanning = true;
  /// Threads of conflict resolution's checks (ScheduleChecker's lanes; 0: the hardware's, at most 2).
  /// Named `validation_threads` with the validator's: the schedule is the same for any number.
  int threads = 0;
};

/// The scheduler's named parameters (staggered_arrivals, idle_arms_home, parking, schedule_memo) from
/// a resolved parameter set (resolveParameters); names it lacks are left alone.
void applySchedulerParameters(SchedulerParams& params, const ParamValues& values);

struct ScheduleStats {
  int delays = 0;       ///< retiming steps taken
  int replans = 0;      ///< moves replanned around robots in the way
  int composite_replans = 0;  ///< subproblems solved in the composite space of several robots
  int reused_steps = 0;       ///< leading steps taken from the last schedule built (ScheduleMemo)
  std::int64_t checks = 0;
};

struct ScheduleResult {
  bool ok = false;
  Plan plan;
  int failed_step = -1;
  std::string reason;
  /// When a step could not be placed because of a conflict nothing resolved: its region (what the
  /// motion constraint C_M learned from it keeps out of), if one can be learned.
  std::optional<ConflictRegion> region;
  ScheduleStats stats;
  std::vector<double> step_times;  ///< when each task step's transition happens (when ok)
};

/// A clock-time window in which robot `robot` may not take part in task step `step` (step -1: its way
/// home): CBS-MP's constraint (robot, vertex or edge, [t0, t1]) as DaSH maps it onto the plan being
/// scheduled (engine/dash/motion_constraint.h). The robot's piece of the step, from leaving for it to
/// the end of its transition (its way home: the whole way), may not overlap [t0, t1): it fits before
/// t0, or it waits where it stands until t1 (safe intervals, as in SIPP). t1 may be +infinity.
struct StepWindow {
  int robot = -1;
  int step = -1;
  double t0 = 0.0;
  double t1 = 0.0;
  bool operator==(const StepWindow&) const = default;
};

/// The earliest start s >= `from` at which a piece of `duration` seconds of robot `robot` in step `step`
/// overlaps none of `windows` (+infinity when a window never ends).
double clearOfWindows(const std::vector<StepWindow>& windows, int robot, int step, double from, double duration);

/// Replans a move for `robot` from -> to in `context` (the robots standing still in context.parked).
using MoveReplanner = std::function<std::optional<std::vector<JointVector>>(
    int robot, const JointVector& from, const JointVector& to, const MotionContext& context)>;

class Scheduler {
 public:
  Scheduler(const CollisionWorld& world, CollisionContext& context, SchedulerParams params = {});

  ScheduleResult build(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                       MotionLayerResult motion, const TaskSpace& space, const MoveReplanner& replan,
                       const Deadline& deadline);
  /// Every later build replans a robot's move into a task step keeping out of the regions of the motion
  /// constraints on that history (nullptr: none), and keeps each robot's piece of a step out of the
  /// clock-time windows of `windows` (nullptr: none; StepWindow). Both must outlive the scheduler's use.
  void respect(const lazy::MotionConstraintSet* constraints, const std::vector<StepWindow>* windows = nullptr) {
    constraints_ = constraints;
    windows_ = windows;
  }
  /// The next build schedules again every step whose motions reach time t (see ScheduleMemo).
  void forgetFrom(double t) { memo_.forgetFrom(t); }
  /// Every later build also checks the robots' configurations at exactly t (ScheduleChecker::alsoCheckAt).
  void alsoCheckAt(double t) { checker_.alsoCheckAt(t); }
  /// Every later build reports its progress through `emitter` (nullptr: none) as ProgressEvents of
  /// conflict resolution (events.h): steps scheduled of the plan's, the robots of the step being
  /// scheduled, steps per second; one when the build starts, then before a step when `interval`
  /// seconds of wall time passed since the last one (0: before every step), one before the robots go
  /// home, and one when it ends (current empty). Reporting only: the schedule does not depend on it.
  void reportProgress(log::EventEmitter* emitter, double interval = 0.5) {
    progress_emitter_ = emitter;
    progress_interval_ = interval;
  }

 private:
  friend struct ScheduleBuild;  // step_scheduler.h: the timing helpers below
  friend class StepScheduler;
  /// Every robot home at the end (when the scene wants it): the motion layer's way home, replanned
  /// around robots standing in the way; why not, or nullopt.
  std::optional<std::string> bringHome(ScheduleBuild& build) const;
  static Plan toPlan(const Scene& scene, ScheduleState& state);
  double duration(int robot, const JointVector& a, const JointVector& b) const;
  void appendPath(RobotTimeline& timeline, double start, const std::vector<JointVector>& path) const;
  double pathDuration(int robot, const std::vector<JointVector>& path) const;
  /// Durations of a composite path's segments: each as long as its slowest mover needs.
  std::vector<double> compositeDurations(const std::vector<int>& robots, const CompositePath& path) const;

  const CollisionWorld* world_;
  CollisionContext* context_;
  SchedulerParams params_;
  ScheduleChecker checker_;
  ScheduleMemo memo_;  ///< the last schedule built, for the next build of a plan that starts the same
  const lazy::MotionConstraintSet* constraints_ = nullptr;
  const std::vector<StepWindow>* windows_ = nullptr;
  log::EventEmitter* progress_emitter_ = nullptr;
  double progress_interval_ = 0.5;
};

}  // namespace dash
