#pragma once
// Execution by dependencies (`options.execution: "tpg"`, issue 39): each node of the plan's temporal
// plan graph (engine/tpg/tpg.h) becomes one goal of its arm, sent when the nodes it waits for are
// reported done by their agents, instead of one timed goal per arm started at a common time.
//  - a motion segment: the plan's points between the node's ends, re-based to 0 and scaled by
//    time_scale; the arm comes to rest at both ends (velocities as arm_trajectory.h, zero at the ends);
//  - a grasp or release: a goal of one point (where the arm stands) and the gripper command at t = 0:
//    it is done when the gripper has finished (a Hand-E closing in a second holds up what waits for it);
//  - a hold (the plan keeps the arm still) or an inspect: nothing to send, done as soon as it may start.
// The path tolerance applies to each segment's own path, not to a clock: a sample is compared with
// the nearest point of the segment's straight joint-space lines (an arm that lags is no fault, one
// that leaves its lines is). A segment that takes longer than segment_time_factor times its planned
// duration plus a margin is given up on (an arm that stalls).
//
// Pure bookkeeping: DispatchService calls it under its lock and sends what it says.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/tpg/tpg.h"
#include "server/dispatch/arm_trajectory.h"
#include "server/dispatch/dispatch_status.h"

namespace dash::dispatch {

struct TpgStep {
  enum class Kind { kMotion, kGripper, kHold, kInspect };
  Kind kind = Kind::kMotion;
  int node = -1;                ///< graph node
  ArmTrajectory goal;           ///< kMotion, kGripper
  double planned_start = 0.0;   ///< s, scaled
  double planned_end = 0.0;
  std::vector<std::pair<int, int>> waits_for;  ///< (arm, step) of other arms
  enum class State { kPending, kSent, kDone };
  State state = State::kPending;
  bool seen_active = false;     ///< the agent reported this goal armed or executing
  std::int64_t start_us = 0;    ///< server time it was sent (or started, for one with nothing to send)
  std::int64_t end_us = 0;
  JointVector q_start, q_end;   ///< measured at start_us and end_us (empty if no sample yet)
  std::string goal_id;          ///< the dispatch id its goal carries: "<dispatch>/<step>"
};

const char* tpgStepKindName(TpgStep::Kind kind);  ///< "motion", "gripper", "hold", "inspect"

class TpgRun {
 public:
  /// The steps of `plan`'s arms, in `robots` order (the dispatch's arms), from `graph`. Throws
  /// InputError if an arm is not in the graph.
  TpgRun(const Plan& plan, const tpg::Graph& graph, const std::vector<std::string>& robots, double time_scale,
         const std::string& dispatch_id);

  int arms() const { return static_cast<int>(steps_.size()); }
  std::vector<TpgStep>& steps(int arm) { return steps_[static_cast<std::size_t>(arm)]; }
  const std::vector<TpgStep>& steps(int arm) const { return steps_[static_cast<std::size_t>(arm)]; }
  /// The first step of `arm` that is not done (steps(arm).size() when all are).
  int current(int arm) const;
  bool armDone(int arm) const { return current(arm) == static_cast<int>(steps(arm).size()); }
  bool allDone() const;
  /// Whether every step the current step of `arm` waits for is done.
  bool mayStart(int arm) const;
  /// "ur5e_1 segment 4 (motion)" for each step the current one waits for that is not done; empty if none.
  std::string waitingFor(int arm, const std::vector<std::string>& robots) const;
  /// The step whose goal carries `goal_id` on `arm`, or -1.
  int stepOfGoal(int arm, const std::string& goal_id) const;
  /// Where the arm should be while its current step runs: the nearest point of the step's path to `q`;
  /// between steps (or waiting), where the last finished step left it.
  JointVector nearestPlanned(int arm, const JointVector& q) const;
  /// Per arm, the executed times of every step so far (s from `start_us`), for the record.
  std::vector<SegmentRecord> records(int arm, std::int64_t start_us) const;
  /// Longest a step may take: factor x its planned duration + margin (+ gripper_allowance for a gripper).
  double allowance(const TpgStep& step, double factor, double margin, double gripper_allowance) const;

 private:
  std::vector<std::vector<TpgStep>> steps_;
};

}  // namespace dash::dispatch
