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
// The greedy pass does not expand moves to a configuration where nothing can happen now (the robot
// can usually go there later, directly, because moves join every exit of a planning space to every
// entry). Under motion constraints that direct move may be forbidden while a detour through such a
// configuration is not, so when the greedy pass exhausts its states, a complete pass searches again
// with every move expanded (those last): over the finite states of H_M (one instance per robot,
// object and task) the depth-first search with its state memo is then complete, so "no hyperpath"
// means none exists in H_M under the constraints. Before it (it rarely ends within its budget on the
// larger scenes: its states are every robot's configuration times every object's state), a pass moves
// one object at a time: only the first object (by index) not yet finished may be picked, handed over,
// carried or placed; robots move as in the greedy pass, and back from a handover whose partner did
// not come (moves the greedy pass leaves out: they let it wander). That pass cannot tangle (robots holding objects, each
// waiting for another to take its own), and it finds a hyperpath whenever each object has a route of
// its own and the robots can get home, which is what a generated scene gives; the scheduler then runs
// the independent steps of different objects side by side.
// A step that leaves a robot where its roadmaps give it no way home (e.g. a place whose empty-handed
// retreat lies in another component of the robot's roadmap than home) is never applicable: the goal
// needs every robot home, and no later step can bring it there (robot reachability over H_M,
// objects ignored, so this prunes nothing a hyperpath could use).
// Motion constraints are CBS-MP's (motion_constraint.h): (robot, vertex or edge, time interval).
#include <unordered_set>
#include <vector>

#include "engine/dash/motion_constraint.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"

namespace dash {

struct CombinedQueryParams {
  std::size_t max_expansions = 200000;             ///< greedy pass
  std::size_t one_object_max_expansions = 1000000;  ///< one-object-at-a-time pass
  std::size_t complete_max_expansions = 4000000;    ///< complete pass (then kBudget, never "none")
  /// Memory cap of one pass, in frontier entries over its states (about 16 bytes each): a pass's
  /// budget is the smaller of its max and this over the number of robots, objects and tasks (the
  /// frontier's size).
  std::size_t max_frontier_entries = 100000000;
  /// Memory cap of a pass's depth-first stack, in successors not yet tried (24 bytes each).
  std::size_t max_pending_successors = 50000000;
  // Beyond DaSH (named parameters, off in --profile paper; dash_params.h):
  /// The greedy pass leaves out moves to where nothing can happen now and moves back from a handover.
  /// Off: its one pass expands every move (the complete pass's order, with its budget), so it is
  /// complete by itself over H_M, and no other pass runs.
  bool prune_moves = true;
  bool one_object_pass = true;  ///< after a failed greedy pass: the one-object-at-a-time pass
  bool complete_pass = true;    ///< after the failed passes: the complete pass
  /// No step may leave a robot with no way home in H_M (strandsRobot); off: strandsRobot is false.
  bool stranding_prune = true;
};

class CombinedQuery {
 public:
  /// `graph` must outlive the query.
  explicit CombinedQuery(const MotionHypergraph& graph);

  /// One query under `constraints`, the cost-to-go included: it is computed for each query over the
  /// hyperarcs that constraints for the whole plan leave. `greedy_only` reports the greedy pass's own
  /// outcome (what the complete pass adds is tested against it).
  HyperpathResult run(const std::vector<MotionConstraint>& constraints, const CombinedQueryParams& params,
                      const Deadline& deadline, std::function<void(const ExtendedVertex&)> on_vertex = {},
                      std::function<void(const ExtendedHyperarc&)> on_hyperarc = {});
  enum class Pass { kGreedy, kComplete, kOneObjectAtATime };
  /// Which pass found the last hyperpath (or ended the last query).
  Pass lastPass() const { return last_pass_; }

  /// Cost-to-go to the object's goal, as of the last run() (or with no constraints before one).
  double costToGo(VertexId v) const { return to_goal_[v.value()]; }

  /// Whether `a` leaves some robot at a vertex from which H_M has no way to its home (as of the last
  /// run(); such a step is never taken).
  bool strandsRobot(HyperarcId a) const { return strands_[a.value()] != 0; }

 private:
  struct Summary;
  void refresh(const std::vector<HyperarcId>& forbidden);
  /// strands_ from the robot vertices that can reach home over hyperarcs not in `forbidden`.
  void refreshStranded(const std::unordered_set<HyperarcId>& forbidden);
  /// The first object (by index) not at its goal (or, while an inspection needs it away, not away
  /// from its start) in `state`; -1 when all are.
  int firstUnfinished(const HyperpathState& state) const;
  /// A place onto a shared placement another object rests at now is not applicable.
  bool placementFree(const HyperpathState& state, HyperarcId a) const;
  /// The greedy order of `which` pass: the greedy pass drops moves to where nothing can happen now
  /// and moves back from a handover; the one-object pass takes moves back (last); the complete pass
  /// takes every move (those two kinds last).
  double priority(const HyperpathState& state, HyperarcId a, Summary& summary, Pass which) const;
  /// priority() of a move hyperarc (summary already filled for state).
  double movePriority(const HyperpathState& state, HyperarcId a, const Summary& summary, Pass which) const;
  /// The object state an object-moving hyperarc leaves and the one it reaches (invalid otherwise).
  std::pair<VertexId, VertexId> objectMove(HyperarcId a) const;
  double regret(const HyperpathState& state, HyperarcId a) const;
  /// to_goal_, or to_away_ for an object a pending inspection needs away from its start.
  double costToGo(const HyperpathState& state, VertexId v) const;

  const MotionHypergraph* graph_;
  std::vector<double> to_goal_;
  std::vector<double> to_away_;
  std::vector<char> strands_;  ///< per hyperarc: strandsRobot()
  std::vector<std::vector<VertexId>> pending_of_;  ///< per object: pending tasks that need it away
  Pass last_pass_ = Pass::kGreedy;
  bool stranding_prune_ = true;  ///< CombinedQueryParams::stranding_prune of the last run()
};

}  // namespace dash
