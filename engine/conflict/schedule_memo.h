#pragma once
// Conflict resolution runs again after every failure fed back to the task query, and the new task plan
// usually begins with the same steps as the last one (the greedy query only parts from it where the new
// constraint bites). The memo keeps the last schedule with a mark after each of its steps, so that the
// next build continues from the first step where the two plans part instead of scheduling the shared
// steps again (on sorting 16x64 a round schedules ~300 steps before it meets the failure).
//
// A step is the same when its task action, its dependencies and its sampled transition are. How the
// motion layer gets there may differ (another transit, a deeper back-off found by another roadmap
// query): the remembered motions were checked against everything scheduled before them and stay
// valid, and the first transit after the shared steps is replanned from wherever the robot stands,
// as after any step.
#include <optional>
#include <vector>

#include "engine/conflict/timeline.h"
#include "engine/plan/plan.h"
#include "engine/task/task_conflict_detection.h"

namespace dash {

/// What the scheduler has built so far.
struct ScheduleState {
  std::vector<RobotTimeline> timelines;
  ObjectTimeline objects;
  std::vector<PlanEvent> events;
  std::vector<double> step_time;  ///< per step of the plan being scheduled
};

class ScheduleMemo {
 public:
  /// How many leading steps of `plan` are the same as the remembered schedule's; when there are any,
  /// `state` becomes the remembered schedule right after them (step_time keeps its size).
  int resume(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions, ScheduleState& state) const;
  /// Starts remembering a new build that keeps the first `steps` remembered steps.
  void restart(int steps);
  /// The next step is now scheduled (its retreats too) and `state` holds it.
  void recordStep(const TaskStep& step, const TransitionConfig& transition, const ScheduleState& state);
  /// The build stopped (done or failed): remembers what it built, to rewind to the marks later.
  void recordEnd(const ScheduleState& state) { last_ = state; }
  /// Forgets the steps after which some robot's schedule already reaches time t (a collision the
  /// validator found there must not be taken again from the memo).
  void forgetFrom(double t);
  int steps() const { return static_cast<int>(keys_.size()); }

 private:
  struct StepKey {
    TaskArc action;
    std::vector<int> after;
    TransitionConfig transition;
  };
  struct StepMark {
    std::vector<RobotTimeline::Mark> robots;
    std::size_t objects = 0;
    std::size_t events = 0;
  };

  std::vector<StepKey> keys_;
  std::vector<StepMark> marks_;
  std::optional<ScheduleState> last_;
};

}  // namespace dash
