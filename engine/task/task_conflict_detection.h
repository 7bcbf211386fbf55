#pragma once
// Task conflict detection (paper, Sec. "Task Conflict Detection Layer", Algorithm 2): trace the
// unvalidated schedule, sample the transition configurations (object poses, and grasp or handover
// configurations by IK guided by the formation constraint), and check them against the static scene
// of that moment. Every conflict of the schedule is collected, not just the first:
//  - a colliding object pose that is not anchored (an extra or resampleable location) is resampled here;
//  - a robot's transition configuration blocked by resting objects becomes frontier constraints
//    (v_pre = the blocker at its location, v_post = the element the transition would produce);
//  - a blocker that would have to leave a location it must also end at, with nowhere else to go,
//    asks for a task space expansion (an extra stable pose for it);
//  - a transition with no collision-free configuration even without objects (a handover through a
//    wall) becomes an interaction constraint. The paper finds these when building the motion
//    hypergraph; here transition configurations are sampled once, in this layer, and reused there.
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "engine/core/deadline.h"
#include "engine/core/rng.h"
#include "engine/task/rejected_configurations.h"
#include "engine/task/task_constraints.h"
#include "engine/task/task_plan.h"
#include "engine/task/transition_sampler.h"

namespace dash {

class MoveOutSampler;

/// The sampled configurations of one task step (valid when `sampled`).
struct TransitionConfig {
  bool sampled = false;
  JointVector q;                   ///< actor: picker, placer, giver or inspector
  JointVector q2;                  ///< handover receiver
  Pose X_WO = Pose::Identity();    ///< the object at the transition
  Pose X_TO = Pose::Identity();    ///< actor's grasp (object in TCP frame)
  Pose X_TO2 = Pose::Identity();   ///< receiver's grasp
};

struct TaskConflictParams {
  int chain_budget = 8000;        ///< sampler calls per object chain
  int grasp_candidates = 6;       ///< per grasp class and pose
  int handover_poses = 1040;      ///< object poses tried per handover (the whole search grid)
  /// Side grasps prefer the IK branch whose approach line is free (beyond the paper).
  bool prefer_free_approach = true;
  /// Times a move-out pose (a resampleable extra location) is resampled because an object's chain has no
  /// collision-free transition configuration at it, before the step is banned for some task queries
  /// (an application of the paper's "resampling is performed to search for valid alternatives", beyond
  /// it; the planner parameter move_out_resamples, off by default, docs/planners.md). With a
  /// MoveOutSampler (resampleMoveOutsWith) the new pose is one that traps no robot; else it is on the
  /// same surface.
  int chain_location_resamples = 0;
};

struct TaskConflictResult {
  std::vector<TransitionConfig> transitions;  ///< one per plan step
  std::vector<TaskConstraint> constraints;    ///< new constraints to add
  std::vector<int> expand_objects;            ///< objects that need an extra stable pose
  std::vector<std::string> conflicts;         ///< what was found, for people and logs
  int resampled = 0;                          ///< object locations moved in this pass
  int move_outs_resampled = 0;                ///< of which: move-out poses with no transition configuration
  bool interrupted = false;                   ///< the deadline expired before the trace was done
  std::size_t configuration_checks = 0;

  bool feasible() const { return !interrupted && constraints.empty() && expand_objects.empty() && resampled == 0; }
};

class TaskConflictDetector {
 public:
  TaskConflictDetector(TransitionSampler& sampler, TaskSpace& space, const TaskHypergraph& graph, Rng& rng,
                       TaskConflictParams params = {});

  /// Configurations to choose only when a chain has no other (the motion layer could not reach them);
  /// `rejected` must outlive the detector.
  void avoid(const RejectedConfigurations& rejected) { rejected_ = &rejected; }
  /// A move-out pose that no grasp chain can use is resampled by `move_outs` (anywhere a robot that
  /// takes the object can carry it) rather than on its own surface; it must outlive the detector.
  void resampleMoveOutsWith(const MoveOutSampler& move_outs) { move_outs_ = &move_outs; }
  /// Stops early (result.interrupted) when the deadline expires.
  TaskConflictResult detect(const TaskPlan& plan, const Deadline& deadline = Deadline());

 private:
  struct Trace;
  void traceLayouts(const TaskPlan& plan, Trace& trace) const;
  bool resolvePoseConflicts(const TaskPlan& plan, const Trace& trace, TaskConflictResult& result);
  bool resampleLocation(int object, int location, const Trace& trace);
  void solveObjectChains(const TaskPlan& plan, const Trace& trace, const Deadline& deadline, TaskConflictResult& result);
  /// Interaction constraints for the handovers of object o's chain that no grasps make possible; whether any.
  bool banImpossibleHandovers(const TaskPlan& plan, const std::vector<int>& chain, int o, TaskConflictResult& result);
  /// The constraint for step k of a chain with no collision-free transition configuration even without
  /// resting objects: a ban for some task queries when the search got past the chain's first
  /// transitions or ran out of budget, else a class ban (handover) or a ban of the hyperarc.
  void banUnservedStep(const TaskPlan& plan, int k, bool past_first_or_budget, TaskConflictResult& result);
  void solveInspections(const TaskPlan& plan, const Trace& trace, TaskConflictResult& result);
  void addBlockerConstraints(const TaskPlan& plan, const Trace& trace, int step, const std::vector<int>& blockers,
                             TaskConflictResult& result);
  VertexId producedElement(const TaskStep& step) const;
  /// Whether robots `giver` and `receiver` can hand `object` over with these grasp classes at all
  /// (no resting objects, any grasps). Static, so cached for the whole run.
  bool handoverPossible(int giver, int receiver, int object, GraspClass g1, GraspClass g2);
  /// A chain with no collision-free transition configuration at chain[at]: where that step places the
  /// object at (or picks it from) a move-out pose, or else an earlier step of the chain does, that pose
  /// is resampled (at most chain_location_resamples times per pose). Returns whether it was.
  bool resampleChainLocation(const TaskPlan& plan, const Trace& trace, const std::vector<int>& chain, std::size_t at,
                             TaskConflictResult& result);

  TransitionSampler* sampler_;
  TaskSpace* space_;
  const TaskHypergraph* graph_;
  Rng* rng_;
  TaskConflictParams params_;
  static inline const RejectedConfigurations kNoneRejected{};
  const RejectedConfigurations* rejected_ = &kNoneRejected;
  const MoveOutSampler* move_outs_ = nullptr;
  std::map<std::tuple<int, int, int, int, long, long, long>, bool> handover_possible_;
  std::map<std::pair<int, int>, int> chain_resamples_;  ///< (object, location): resampleChainLocation's
};

}  // namespace dash
