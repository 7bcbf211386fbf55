#pragma once
// DaSH's combined task-and-motion query (paper, "Comparison with DaSH": "the combined task and motion
// planning query phase finds a solution within the constructed representation"): the greedy hyperpath
// query of engine/hypergraph run on the motion hypergraph H_M itself, with motion costs (roadmap path
// lengths, approach and retreat lengths) as hyperarc costs. The extended hypergraph it builds is H_ME.
//
// Cost-to-go: per object, a backward Dijkstra over its states in H_M (resting at a placement, held at
// a configuration) from its goal, through picks, places, handovers and moves while held; robots alone
// cost nothing. An object a pending inspection needs out of the way (a lab lid) counts its cost to
// any placement but its start instead, until the inspection is done. The greedy order (lowest first; the search is depth-first with backtracking):
//  1. the sink; then transitions that are applicable now, in order of regret (cost plus the object's
//     cost-to-go after minus before: 0 on a cheapest route), handovers and places before picks;
//  2. moves of robots holding an object, towards a transition that is possible now (a place, or a
//     handover whose receiver has an empty hand), by regret;
//  3. moves of empty-handed robots to a transition that is possible now: receiving an object another
//     robot holds, then inspecting, then picking an object that rests there, by regret plus path cost;
//  4. transitions and moves off the cheapest routes, then moves home, then steps that take an object
//     away from its goal.
// A shared placement (placement_sampling.h) holds one object at a time: a place onto it is applicable
// only while no other object rests there (a property of the representation, not a learned constraint).
// Moves to a configuration where nothing can happen now are not expanded: the robot can still go
// there later, directly, because moves join every exit of a planning space to every entry.
// Motion constraints forbid hyperarcs outright (the `forbidden` set).
#include <unordered_set>
#include <vector>

#include "engine/dash/motion_hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"

namespace dash {

struct CombinedQueryParams {
  std::size_t max_expansions = 200000;
};

class CombinedQuery {
 public:
  /// `graph` must outlive the query.
  explicit CombinedQuery(const MotionHypergraph& graph);

  /// One query with the hyperarcs in `forbidden` (motion constraints) left out, the cost-to-go
  /// included: it is computed for each query over what the constraints leave.
  HyperpathResult run(const std::unordered_set<HyperarcId>& forbidden, const CombinedQueryParams& params,
                      const Deadline& deadline, std::function<void(const ExtendedVertex&)> on_vertex = {},
                      std::function<void(const ExtendedHyperarc&)> on_hyperarc = {});

  /// Cost-to-go to the object's goal, as of the last run() (or with no constraints before one).
  double costToGo(VertexId v) const { return to_goal_[v.value()]; }

 private:
  struct Summary;
  void refresh(const std::unordered_set<HyperarcId>& forbidden);
  /// A place onto a shared placement another object rests at now is not applicable.
  bool placementFree(const HyperpathState& state, HyperarcId a) const;
  double priority(const HyperpathState& state, HyperarcId a, Summary& summary) const;
  /// The object state an object-moving hyperarc leaves and the one it reaches (invalid otherwise).
  std::pair<VertexId, VertexId> objectMove(HyperarcId a) const;
  double regret(const HyperpathState& state, HyperarcId a) const;
  /// to_goal_, or to_away_ for an object a pending inspection needs away from its start.
  double costToGo(const HyperpathState& state, VertexId v) const;

  const MotionHypergraph* graph_;
  std::vector<double> to_goal_;
  std::vector<double> to_away_;
  std::vector<std::vector<VertexId>> pending_of_;  ///< per object: pending tasks that need it away
};

}  // namespace dash
