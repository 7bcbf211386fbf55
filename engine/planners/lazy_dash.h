#pragma once
// Lazy-DaSH: S. Lee, J. Motes, I. Ngui, M. Morales, N. M. Amato, "Lazy-DaSH: Lazy Approach for
// Hypergraph-based Multi-robot Task and Motion Planning". DaSH's hypergraph planner (Motes et al.,
// T-RO 2023) made lazy at three stages (the paper's Algorithm 1): the task query defers motion
// feasibility to the motion layer; the motion hypergraph is built over edge-unvalidated roadmaps and
// validated in the motion query; conflict resolution replans lazily with motion constraints.
// Task conflict detection (Algorithm 2) and task space expansion happen before any motion is planned.
#include <utility>

#include "engine/collision/collision_world.h"
#include "engine/conflict/scheduler.h"
#include "engine/core/planner_params.h"
#include "engine/motion/motion_layer.h"
#include "engine/planners/planner.h"
#include "engine/task/task_layer.h"

namespace dash {

/// Every field that is a named planner parameter (engine/core/planner_params.h) has the registry's
/// default; applyParameters sets them from a resolved set.
struct LazyDashParams {
  MotionLayerParams motion;
  TaskLayerParams task;
  SchedulerParams scheduler;
  /// Transition configurations of one task hyperarc that the motion layer or conflict resolution may
  /// turn down (no way to them, or a handover that cannot be scheduled) before the hyperarc itself goes
  /// back to the task query as a ban.
  int max_transition_resamples = 2;
  /// Metres every check of the planner keeps between parts not in contact by design (collision_world.h).
  double clearance = kDefaultPlanningClearance;
  /// Threads of the validator run on each schedule (0: the hardware's); its report, hence the plan,
  /// is the same for any number.
  int validation_threads = 0;
  bool budget_growth = true;     ///< roadmap budgets raised when a failure has no alternative
  int validator_rechecks = 3;    ///< per round: schedule again checking the validator's contact instant
  /// Per attempt: validator contacts fed back as task constraints; one more ends the attempt (a restart,
  /// or with restarts off the run). At 5, stocking 2 layers / 28 objects seed 1 ended "infeasible"
  /// after 500 s; it needs more.
  int validation_feedbacks = 100;
  /// Motion rounds on one task plan (Algorithm 1's inner loop) before its failure becomes a task constraint.
  int motion_budget = 3;
  /// When the task query, the feedback loop or the task rounds have nothing left to try: restart with
  /// every task constraint lifted, fresh samples and larger roadmap budgets, until the deadline. Off
  /// (the paper): the run ends "infeasible" there, which a sampling-based planner cannot prove.
  bool restart_when_exhausted = true;
  /// Task plans one attempt tries (Algorithm 1's outer loop) before it counts as exhausted.
  int max_task_plans = 200;
};

/// Sets the fields named by `values` (a resolveParameters("lazy-dash", ...) set, or part of one).
void applyParameters(LazyDashParams& params, const ParamValues& values);

class LazyDash final : public Planner {
 public:
  explicit LazyDash(LazyDashParams params = {}) : params_(std::move(params)) {}
  std::string name() const override { return "lazy-dash"; }
  PlanResult solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                   log::EventSink* sink) override;

 private:
  LazyDashParams params_;
};

}  // namespace dash
