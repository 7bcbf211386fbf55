#pragma once
// The region p of a motion conflict that conflict resolution could not resolve (paper, "Motion
// Conflict Resolution and Constraint Feedback": "motion constraints are applied to prevent traversal
// through regions defined by the boundaries of colliding objects and robots"). Which move must go
// around what:
//  - a robot's move against another robot (hyperarc-hyperarc): the move of the robot that was being
//    placed goes around the parts of the other robot (bodies, held object) over the conflict's time
//    window [t, t + window], each part's swept box over that window;
//  - a robot's move against a resting object (hyperarc-vertex): the move goes around the object's box;
//  - an object being placed where another robot passes: that robot's move at that time goes around the
//    object's box at its placement.
// Every box is grown by the planner's clearance. Obstacles give no region (nothing to learn: the motion
// layer already plans around them).
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/conflict/schedule_checker.h"
#include "engine/conflict/schedule_memo.h"
#include "engine/task/task_conflict_detection.h"
#include "engine/task/task_plan.h"

namespace dash {

struct ConflictRegion {
  int robot = -1;        ///< whose move goes around the region (the constrained history, Pi_1)
  int step = -1;         ///< the task step that move leads into
  JointVector q;         ///< the robot's transition configuration at that step
  int other = -1;        ///< the robot in the way (Pi_2), or -1
  int other_step = -1;   ///< its task step at the conflict's time
  int object = -1;       ///< the resting object in the way, or -1
  std::vector<Aabb> boxes;
  double t_begin = 0.0;  ///< seconds into the schedule
  double t_end = 0.0;
};

/// The task step robot `robot` is moving into at time t of a schedule: its first step whose transition
/// is at or after t, else its last step before t; -1 when it has none. `step_times` per step of `plan`.
int stepOfRobotAt(const TaskPlan& plan, const std::vector<double>& step_times, int robot, double t);

/// The conflict's two robots as the trial that met it had them (null: as `state` has them, or none).
struct TrialTimelines {
  const RobotTimeline* robot = nullptr;
  const RobotTimeline* other = nullptr;
};

/// The region of `conflict`, met while placing step `failed_step` of `plan` with transition
/// configurations `transitions` (one per step) in the schedule `state`. Between two robots the region is the other robot's parts
/// that meet the robot's over the window (the colliding parts; all of them when the window's boxes
/// miss, the contact lying between its instants). nullopt when nothing can be learned (an obstacle, or
/// no step to constrain).
std::optional<ConflictRegion> conflictRegion(const CollisionWorld& world, CollisionContext& context,
                                             const ScheduleState& state, const TaskPlan& plan, int failed_step,
                                             const std::vector<TransitionConfig>& transitions,
                                             const ScheduleConflict& conflict, TrialTimelines trial, double window);

}  // namespace dash
