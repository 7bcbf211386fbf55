#pragma once
// Task query (paper, "Query (Task-extended Hypergraph)"): builds H_TE from the source by expanding
// task hyperarcs whose whole tail is on the frontier, greedily by an estimated cost-to-go, with
// backtracking, and never expanding what the task constraints forbid. The result is an unvalidated
// schedule.
#include <functional>

#include "engine/core/deadline.h"
#include "engine/hypergraph/hyperpath_search.h"
#include "engine/task/task_constraints.h"
#include "engine/task/task_heuristic.h"
#include "engine/task/task_plan.h"

namespace dash {

struct TaskQueryParams {
  HyperpathAlgorithm algorithm = HyperpathAlgorithm::kGreedy;
  std::size_t max_expansions = 400000;
  bool remove_round_trips = true;  ///< removeRoundTrips on the found plan (beyond the paper)
};

struct TaskQueryResult {
  HyperpathStatus status = HyperpathStatus::kExhausted;
  TaskPlan plan;
  HyperpathStats stats;
  /// An object with no route to its goal left by the interaction constraints (the search was not
  /// run: kExhausted), or -1.
  int unroutable_object = -1;
  bool found() const { return status == HyperpathStatus::kFound; }
};

/// Observers of H_TE growth (extended vertices and hyperarcs), for the event stream.
struct TaskQueryObserver {
  std::function<void(const ExtendedVertex&)> onVertex;
  std::function<void(const ExtendedHyperarc&)> onHyperarc;
};

TaskQueryResult queryTaskPlan(const TaskHypergraph& graph, const TaskSpace& space,
                              const TaskConstraintSet& constraints, const TaskQueryParams& params,
                              const Deadline& deadline, const TaskQueryObserver& observer = {});

}  // namespace dash
