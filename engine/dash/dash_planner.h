#pragma once
// DaSH (Decomposable State Space Hypergraph; Motes, Chen, Bretl, Morales, Amato, IEEE T-RO 39(5),
// 2023), the baseline of the Lazy-DaSH paper (Lee et al., see lazy_dash.h; "Comparison with DaSH",
// "Method Descriptions"), on the workbench's geometry:
//  1. task space hypergraph H_T with location-free object elements (dash_task_graph.h) and
//     pre-sampled object placements besides each object's start and goal;
//  2. motion hypergraph H_M built exhaustively before any query (motion_hypergraph.h): transition
//     configurations for every transition of H_T (transition_catalog.h), fully validated PRM roadmaps
//     (og::PRM, validated_roadmap.h) and move hyperarcs joining every transition in every planning
//     space; every collision check here is "eager";
//  3. the combined task-and-motion query on H_M (combined_query.h): the greedy hyperpath query with
//     motion costs and backtracking; by default it prunes moves and is followed, when it finds
//     nothing, by a one-object pass and a complete pass (additions beyond DaSH, named parameters,
//     dash_params.h); with --profile paper it is one pass that expands every move, complete by itself;
//  4. conflict resolution: resting-object conflicts by CBS-MP's low-level search (resting_conflicts.h),
//     robot-robot conflicts by the Scheduler Lazy-DaSH also uses (the paper gives both planners the
//     same scheduler "for a fair comparison"), with the same memo of the last schedule and the same
//     re-checks of contacts the validator finds (a contact that stays is a conflict, never an error);
//     an unresolved conflict triggers CBS-MP's probabilistic break rule (break_rule.h): the roadmaps
//     of the robots involved grow and the same node is queried again, or the constraint tree grows by
//     one child per robot involved, each with a CBS-MP constraint (motion_constraint.h: robot, vertex
//     or edge of H_M, time interval).
// The transition candidates (grasps, handover poses, approach-line checks, back-off depths) are
// Lazy-DaSH's (transition_catalog.h). Like any PRM-based planner DaSH never declares a problem
// infeasible: a root without a hyperpath, or an exhausted constraint tree, grows every roadmap and
// starts again, until the deadline.
// Counters in the event stream: "constraint_tree_nodes" (queries), "roadmap_growths" and
// "constraint_tree_branchings" (the break rule's decisions), "constraint_tree_restarts",
// "one_object_query_passes" and "complete_query_passes" (queries the greedy pass did not answer, by
// the pass that ended them), "validation_rechecks", "validation_feedbacks".
// The run is a DashRun (dash_run.h), whose methods are these steps.
// DaSH has no task conflict detection and no task space expansion: only motion constraints drive its
// replanning. That is what the paper shows failing on Wall, Shelf-wall and Stocking.
//
// Departures, on purpose: the constraint tree is searched depth-first (the greedy query is not
// cost-optimal, so CBS's best-first order buys nothing); a move hyperarc's path is the roadmap's
// shortest path, shortened only by conflict resolution's replanning.
#include "engine/dash/dash_params.h"
#include "engine/planners/planner.h"

namespace dash {

class DashPlanner final : public Planner {
 public:
  explicit DashPlanner(DashParams params = {}) : params_(params) {}
  std::string name() const override { return "dash"; }
  PlanResult solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                   log::EventSink* sink) override;

 private:
  DashParams params_;
};

}  // namespace dash
