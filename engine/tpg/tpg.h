#pragma once
// The temporal plan graph (TPG) of a validated plan: execution by dependencies instead of by the clock
// (issue 39; the idea is APEX-MR's, RSS 2025). Each arm's timeline is cut into nodes, in time order:
// motion segments (the plan's straight joint-space lines between two cuts, holds included) and events
// (its grasps, releases and inspects, instantaneous). An arm runs its nodes in order; a node may also
// have to wait for nodes of other arms (edges, "from must be done before to starts"):
//  - handover: the receiver grasps only once the giver stands at its handover configuration, and the
//    giver neither moves on nor releases before that grasp; the giver's release waits for the
//    receiver to stand where the plan has it then, and the receiver carries the object away only
//    after that release;
//  - object: a segment whose parts (bodies and held object) come within the clearance of an object
//    resting somewhere waits for the release that put it there, or the grasp that takes it away
//    waits for the segment, as the plan ordered them;
//  - swept: two segments of different arms whose swept volumes (every pose each takes, with what it
//    holds) come within the clearance are ordered as the plan placed them. Segments that overlap in
//    time in the plan are cut finer until they no longer meet, or one of them holds still and the
//    other runs entirely while it does (then the other waits for the holder to arrive and the holder
//    waits for it to end). Contact the plan means (a gripper and the object another robot holds, of
//    a handover it is in) may touch but not overlap, as the validator has it.
// The aim: every execution that respects the graph, whatever each node's delay or speed, keeps each
// pair that meets in the order the plan had it, so it passes the plan's own checks. The contact pair
// is measured as the validator measures it (every contact_floor of motion, not proved apart: a
// touching pair cannot be), so where two arms approach a handover at once their approaches are cut
// and ordered until no delay puts a finger into the held object (docs/dispatch.md, "Handover
// contact"). `dashbench tpg --check N` replays random executions through the certified validator
// (tpg_replay.h).
//
// Stored as the optional "tpg" field of dashbench.plan/1 (docs/formats.md): tpgToJson / parseTpg.
#include <functional>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/scene/scene.h"

namespace dash::tpg {

inline constexpr const char* kTpgFormat = "dashbench.tpg/1";

struct Node {
  enum class Kind { kMotion, kEvent };
  Kind kind = Kind::kMotion;
  int robot = -1;     ///< index into Plan::robots
  double t0 = 0.0;    ///< planned start (s)
  double t1 = 0.0;    ///< planned end (s); t1 == t0 for an event
  int event = -1;     ///< kEvent: index into Plan::events
  bool moves = false; ///< kMotion: the arm moves (false: it holds still)
};

struct Edge {
  enum class Why { kHandover, kObject, kSwept };
  int from = -1;  ///< node index: must be done ...
  int to = -1;    ///< ... before this node starts
  Why why = Why::kSwept;
};

const char* edgeWhyName(Edge::Why why);  ///< "handover", "object", "swept"

struct Graph {
  double clearance = 0.0;                 ///< m: what "meet" meant when it was built
  std::vector<std::string> robots;        ///< Plan::robots order
  std::vector<Node> nodes;                ///< per robot contiguous, in time order; robots in order
  std::vector<Edge> edges;                ///< between nodes of different robots only
  int forced = 0;  ///< overlapping pairs left meeting at the finest cut, ordered by start (0 in a sound graph)

  /// Node indices of robot r, in order.
  std::vector<int> armNodes(int r) const;
  /// Per node, the nodes it waits for: its predecessor on its arm, then its edges' sources.
  std::vector<std::vector<int>> predecessors() const;
};

struct BuildOptions {
  double clearance = 0.002;      ///< m: parts closer than this "meet" (default: the planners' clearance)
  /// m: sweeps are told apart to this (a closer pair counts as meeting).
  double resolution = 0.0005;
  /// m of motion: a handover's gripper and the held object it takes or lets go may touch but not
  /// overlap (deeper than contact_tolerance); like the validator, they are measured this finely (its
  /// certify_floor) rather than proved apart, since a touching pair cannot be.
  double contact_floor = 5e-5;
  double contact_tolerance = 5e-7;  ///< m: half the validator's touch tolerance (1e-6)
  double min_cut = 0.002;        ///< m of motion: overlapping segments are not cut finer than this
  int max_evaluations = 20000;   ///< per pair of segments the plan runs at once: past it they count as meeting
  /// Per pair the plan runs one after the other: past it they count as meeting, which only adds an
  /// edge the plan's own timing already keeps (a pair proved apart needs no edge).
  int max_ordered_evaluations = 400;
  /// Called after each cutting round with a line on it (pieces, pairs tested, evaluations); may be empty.
  std::function<void(const std::string&)> progress;
};

struct BuildStats {
  int pieces = 0;            ///< motion pieces before merging (cuts at points and events)
  int evaluations = 0;       ///< distance evaluations
  int rounds = 0;            ///< cutting rounds
};

/// The graph of `plan` (which should pass the plan validator). Throws InputError if the plan's robots
/// are not the scene's or a handover is not one the graph can express.
Graph buildGraph(const Scene& scene, const Plan& plan, const BuildOptions& options = {}, BuildStats* stats = nullptr);

/// Structural check of a graph against its plan: robots, node order and cover of each arm's
/// timeline, events, edge ends, no cycle. Empty when fine, else the first problem.
std::string graphProblem(const Graph& graph, const Plan& plan);

/// The "tpg" field: {"format", "clearance", "forced", "nodes": [...], "edges": [...]} (compact JSON).
std::string tpgToJson(const Graph& graph, const Plan& plan);
/// Parses the field (Plan::tpg); throws InputError naming the field. Bounded: at most 1e6 nodes and
/// 4e6 edges. Checks the result with graphProblem.
Graph parseTpg(const std::string& json_text, const Plan& plan);

}  // namespace dash::tpg
