#pragma once
// From a hyperpath of the combined query to what conflict resolution schedules: the transitions in
// the hyperpath's order as a task plan (with the partial order of the hyperpath: a transition waits
// for the transitions that produced what it consumes, through any moves in between), their sampled
// configurations, and per robot its visits (the moves since its previous transition joined into one
// transit, then approach, transition, retreat) and its way home. The same structures Lazy-DaSH's
// motion layer produces, so both planners share one Scheduler (the Lazy-DaSH paper, "Method
// Descriptions": both methods use the scheduled adaptive robot coordination of "Motion Conflict
// Resolution Layer"; DaSH as in "Comparison with DaSH").
#include <array>
#include <vector>

#include "engine/dash/motion_hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"
#include "engine/motion/motion_layer.h"
#include "engine/task/task_conflict_detection.h"
#include "engine/task/task_plan.h"

namespace dash {

struct ExtractedPlan {
  TaskPlan plan;                                ///< TaskStep::arc holds the H_M transition hyperarc
  std::vector<TransitionConfig> transitions;    ///< per plan step
  MotionLayerResult motion;                     ///< visits per robot, in plan order; status kOk
  /// Per plan step, per participant (0: actor or giver, 1: receiver): the move hyperarcs of its transit.
  std::vector<std::array<std::vector<HyperarcId>, 2>> step_moves;
  std::vector<std::vector<HyperarcId>> home_moves;  ///< per robot: moves after its last transition
};

ExtractedPlan extractPlan(const MotionHypergraph& graph, const HyperpathResult& path);

}  // namespace dash
