#pragma once
// The task planning layer of Lazy-DaSH (paper, Algorithm 1, lines 4-7, with Algorithm 2): build H_T,
// query an unvalidated schedule, detect task conflicts, feed back task constraints or expand the task
// space, and repeat until the schedule is task-level feasible. The motion layer reports what it learns
// (infeasible transitions, blocked motions) through addConstraint(), then asks for a new plan.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>

#include "engine/core/deadline.h"
#include "engine/core/rng.h"
#include "engine/events/event_emitter.h"
#include "engine/task/geometric_reachability.h"
#include "engine/task/move_out_sampler.h"
#include "engine/task/task_conflict_detection.h"
#include "engine/task/task_query.h"

namespace dash {

struct TaskLayerParams {
  TaskQueryParams query;
  TaskConflictParams conflicts;
  ReachabilityParams reachability;
  int max_iterations = 1000;
  int max_extra_locations_per_object = 3;
  /// Task space expansion first looks for move-out poses that trap no robot (MoveOutSampler; beyond the
  /// paper; planner parameter move_out_one_grasp, off by default: docs/planners.md says why).
  bool move_out_one_grasp = false;
  /// Times a run may lift the temporary bans when no schedule avoids them (the motion budget is then
  /// raised, a bounded number of times: LazyDash). On large scenes independent failures meet often.
  int max_ban_lifts = 20;
  /// A hyperarc the motion layer fails on again is banned for as many task queries as it has failed
  /// (at most this many), so that alternatives get tried instead of two failing ones alternating.
  int max_ban_queries = 8;
  /// A motion failure at a handover bans the handover class (robots, grasps), not just the hyperarc
  /// (beyond the paper).
  bool handover_class_bans = true;
};

enum class TaskLayerStatus { kFeasible, kInfeasible, kTimeout };
const char* toString(TaskLayerStatus status);

struct TaskLayerResult {
  TaskLayerStatus status = TaskLayerStatus::kInfeasible;
  TaskPlan plan;
  std::vector<TransitionConfig> transitions;  ///< per plan step
  std::string reason;                         ///< why not feasible
  /// The query had no schedule without the hyperarcs the motion layer failed on, so those bans were
  /// lifted: the motion layer should search harder on the same hyperarcs.
  bool motion_bans_lifted = false;
  /// Infeasible because an object has no route to its goal in H_T with no interaction constraint in
  /// force: no robot can take it there (its goal is out of every robot's reach). Lifting constraints
  /// or resampling cannot change that; a generated scene never has it.
  bool no_route_in_task_hypergraph = false;
};

/// Sizes of the task-level representations: H_T as built, H_TE summed over all queries.
struct TaskLayerSizes {
  std::size_t task_vertices = 0;
  std::size_t task_hyperarcs = 0;
  std::size_t task_extended_vertices = 0;
  std::size_t task_extended_hyperarcs = 0;
};

class TaskLayer {
 public:
  TaskLayer(const Scene& scene, const CollisionWorld& world, CollisionContext& context, log::EventEmitter& emitter,
            std::uint64_t seed, TaskLayerParams params = {});

  /// Loops until the schedule is task-level feasible, infeasible, or the deadline passes.
  TaskLayerResult plan(const Deadline& deadline);
  /// Adds a constraint (emitting its event); false if it was already known.
  bool addConstraint(const TaskConstraint& c);
  /// The motion layer found no way to robot r's transition configuration q (or conflict resolution could
  /// not schedule the handover at it): task conflict detection chooses another from now on while there
  /// is another (the region of a motion constraint, which the caller logs); false if q was already
  /// rejected.
  bool rejectTransition(int robot, const JointVector& q);
  /// Algorithm 1's inner loop: task conflict detection again on the same task plan, choosing transition
  /// configurations outside the rejected ones. The new configurations when the plan stays task-level
  /// feasible without new task constraints; nullopt otherwise (nothing is added: the caller feeds the
  /// failure back to the task query).
  std::optional<std::vector<TransitionConfig>> resampleTransitions(const TaskPlan& plan, const Deadline& deadline);
  /// Nothing left to try: every task constraint is lifted (logged with `why`), every rejected
  /// transition configuration is forgotten, and task conflict detection and expansion draw from a fresh
  /// random stream. H_T and its expansions stay. A sampling-based planner never proves a problem
  /// infeasible; this is how Lazy-DaSH goes on until its deadline.
  void restart(const std::string& why);
  int restarts() const { return restarts_; }

  const TaskSpace& space() const { return space_; }
  const TaskHypergraph& graph() const { return graph_; }
  const TaskConstraintSet& constraints() const { return constraints_; }
  TaskLayerSizes sizes() const;
  int queries() const { return queries_; }
  TransitionSampler& sampler() { return sampler_; }

 private:
  void rebuild();
  struct Lifted {
    bool any = false;     ///< some temporary constraint was lifted
    bool motion = false;  ///< among them, one fed back from the motion layer or conflict resolution
  };
  /// Removes the temporary constraints (motion failures, grasp chain failures), logging each as lifted.
  Lifted liftTemporaryConstraints(const std::string& why);
  /// Counts one answered task query down on the temporary constraints, logging those that expire.
  void expireTemporaryConstraints();
  bool expand(int object, const std::string& reason);
  std::vector<int> objectsToExpandAfterFailure() const;
  bool holdsTemporaryMotionBans() const;
  /// After a failed query: move-out states for the objects of the constraints (false if none was added).
  bool expandAfterFailure(const TaskQueryResult& query);
  /// After a failed query: the temporary constraints lifted (false if none, or no lifts left).
  bool liftAfterFailure(TaskLayerResult& result);
  /// The observer of the task query: counts (and logs) H_TE's vertices and hyperarcs.
  TaskQueryObserver queryObserver();
  bool recoverFromFailedQuery(const TaskQueryResult& query, TaskLayerResult& result);
  int applyConflicts(const TaskConflictResult& conflicts);

  const Scene* scene_;
  log::EventEmitter* emitter_;
  TaskLayerParams params_;
  std::uint64_t seed_;
  Rng rng_;
  TaskSpace space_;
  TransitionSampler sampler_;
  GeometricReachability reachability_;
  MoveOutSampler move_outs_;
  TaskHypergraph graph_;
  TaskConstraintSet constraints_;
  RejectedConfigurations rejected_;
  int ban_lifts_ = 0;
  std::int64_t move_outs_resampled_ = 0;  ///< counter move_out_resamples: TaskConflictResult's, summed
  std::unordered_map<std::uint64_t, int> motion_failures_;  ///< per banned hyperarc or handover class
  std::size_t extended_vertices_ = 0;
  std::size_t extended_hyperarcs_ = 0;
  int queries_ = 0;
  int restarts_ = 0;
};

}  // namespace dash
