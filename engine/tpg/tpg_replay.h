#pragma once
// Replays of a plan that respect its temporal plan graph (tpg.h): each node may start late and run
// slower than planned, and starts only once its predecessors (its arm's previous node, its edges'
// sources) are done. The replayed timetable is a plan again (the same joint-space lines, re-timed;
// an arm that waits holds still), so the certified validator (engine/plan/plan_validator.h) can check
// it: `dashbench tpg --check N` runs N random draws. A graph missing an edge it needs fails some draw.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/plan/plan_validator.h"
#include "engine/scene/scene.h"
#include "engine/tpg/tpg.h"

namespace dash::tpg {

/// When each node starts and ends in one execution (s from the common start).
struct Timing {
  std::vector<double> start;
  std::vector<double> end;
  double makespan() const;
};

/// The earliest execution in which node i waits wait[i] after its predecessors are done and runs
/// stretch[i] (>= 1) times its planned duration. Events take no time.
Timing schedule(const Graph& graph, const std::vector<double>& wait, const std::vector<double>& stretch);

/// The plan re-timed to `timing` (points mapped linearly inside each node; holds where an arm waits),
/// its events at their nodes' starts, its makespan the new last time.
Plan replayPlan(const Plan& plan, const Graph& graph, const Timing& timing);

struct ReplayOptions {
  int draws = 100;
  std::uint64_t seed = 1;
  double wait_probability = 0.5;  ///< chance that a node waits at all
  double max_wait = 2.0;          ///< s: a waiting node waits uniformly up to this
  double max_stretch = 2.0;       ///< each node runs 1 .. this times its planned duration
  int focus = -1;                 ///< >= 0: only this node is delayed (draws aimed at one edge)
  ValidationOptions validation;   ///< the certified check of each replay
  /// Called on each failed draw with its timing and the validator's report (may be empty).
  std::function<void(int draw, const Timing&, const ValidationReport&)> on_failure;
};

struct ReplayReport {
  int draws = 0;
  int failed = 0;
  int first_failed_draw = -1;
  std::string first_problem;      ///< the validator's first problem of the first failed draw
  double planned_makespan = 0.0;
  double min_makespan = 0.0, max_makespan = 0.0;  ///< over the draws
};

/// Draw 0 runs every node at once and at its planned speed; the others are random (seeded per draw).
ReplayReport checkReplays(const Scene& scene, const Plan& plan, const Graph& graph, const ReplayOptions& options);

/// The graph without edge `index` (for the check that an edge was needed).
Graph withoutEdge(Graph graph, std::size_t index);

}  // namespace dash::tpg
