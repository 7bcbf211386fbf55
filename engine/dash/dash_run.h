#pragma once
// One DaSH run (dash_planner.h; Motes et al., T-RO 2023, as the Lazy-DaSH paper describes it in
// "Comparison with DaSH" and "Method Descriptions"), as an object whose methods are the algorithm's
// steps: build H_T with pre-sampled placements, build H_M exhaustively (every transition, validated
// roadmaps, every move), then search CBS-MP's constraint tree depth first: query the node (the
// combined task-and-motion query), resolve its conflicts (resting objects, then the scheduler and the
// validator), and on a conflict apply the probabilistic break rule (grow roadmaps, or branch).
// Internal to engine/dash.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "engine/collision/collision_world.h"
#include "engine/core/rng.h"
#include "engine/dash/dash_params.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/plan_extraction.h"
#include "engine/dash/resting_conflicts.h"
#include "engine/events/event_emitter.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/planners/planner.h"
#include "engine/task/geometric_reachability.h"

namespace dash {

class DashRun {
 public:
  /// `params` with the settings' named parameters applied; everything must outlive the run.
  DashRun(const DashParams& params, std::string planner_name, const Scene& scene, const PlannerSettings& settings,
          const Deadline& deadline, log::EventSink* sink);
  ~DashRun();
  DashRun(const DashRun&) = delete;
  DashRun& operator=(const DashRun&) = delete;

  PlanResult solve();

 private:
  using Node = std::vector<MotionConstraint>;
  /// What conflict resolution made of a node's hyperpath: a valid plan, a conflict, or a bug.
  struct NodeOutcome {
    std::optional<Plan> plan;
    std::optional<MotionConflict> conflict;
    std::string internal_error;  ///< non-empty: the validator found something that is not a contact
  };

  // The algorithm's steps.
  void buildTaskSpace();
  void buildMotionHypergraph();
  PlanResult searchConstraintTree();
  HyperpathResult queryNode(const Node& node);
  void growAfterNoHyperpath();
  NodeOutcome resolveConflicts(ExtractedPlan& extracted, const Node& node);
  void respectWindows(const ExtractedPlan& extracted, const Node& node);
  NodeOutcome scheduleAndValidate(ExtractedPlan& extracted);
  void breakRule(const Node& node, const MotionConflict& conflict);
  void growRoadmaps(const std::vector<int>& robots);

  // Bookkeeping.
  std::string unroutedObjects() const;
  std::int64_t checks() const;
  void roadmapTotals(std::int64_t& vertices, std::int64_t& edges) const;
  void emitCounters();
  PlanResult finish(PlanOutcome outcome, std::string message);
  PlanResult timeout(const std::string& where);

  DashParams params_;
  std::string name_;
  const Scene& scene_;
  const PlannerSettings& settings_;
  const Deadline& deadline_;
  OmplSeedScope ompl_seeds_;
  log::EventEmitter emitter_;
  /// Every second of the run is in one phase: setup and the loop's bookkeeping are "other" (open from
  /// construction to finish; the layers' phases pause it), as for Lazy-DaSH (docs/planners.md "Phases").
  log::PhaseTimer other_;
  CollisionWorld world_;
  CollisionContext context_;
  Rng rng_;
  TaskSpace space_;
  TransitionSampler sampler_;
  GeometricReachability reach_;
  DashTaskGraph task_graph_;
  TransitionCatalog catalog_;
  std::unique_ptr<MotionHypergraph> motion_;
  RoadmapSet roadmaps_;
  std::unique_ptr<CombinedQuery> query_;
  std::unique_ptr<Scheduler> scheduler_;
  std::vector<StepWindow> windows_;  ///< the clock-time windows of the node being scheduled (respectWindows)
  std::unique_ptr<BreakRule> break_rule_;
  std::vector<int> all_robots_;
  // The constraint tree: open nodes (depth first) and every node made so far.
  std::vector<Node> open_;
  std::set<Node> seen_;
  std::string last_failure_;
  std::function<void(const ExtendedVertex&)> on_vertex_;
  std::function<void(const ExtendedHyperarc&)> on_hyperarc_;
  PlanResult result_;
  // Counters (the event stream's and the result's).
  std::int64_t eager_ = 0, lazy_ = 0;
  std::size_t extended_vertices_ = 0, extended_hyperarcs_ = 0;
  int motion_constraints_ = 0, queries_ = 0;
  std::int64_t rechecks_ = 0, validation_feedbacks_ = 0, reused_steps_ = 0, restarts_ = 0;
  std::int64_t complete_passes_ = 0, one_object_passes_ = 0;
};

}  // namespace dash
