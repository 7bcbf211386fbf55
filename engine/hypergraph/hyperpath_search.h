#pragma once
// Hyperpath search over the extended hypergraph (the task-extended hypergraph H_TE of Lazy-DaSH,
// Sec. "Query (Task-extended Hypergraph)"; the greedy and Dijkstra/A*-like queries of DaSH, Motes et
// al., T-RO 2023). A search state is a frontier: a multiset of vertex instances (extended vertices),
// each an instance of a hypergraph vertex produced by one step of the history. A hyperarc is applicable
// when every vertex of its tail has an instance on the frontier (until then it is a "partial
// hyperarc"); applying it consumes one instance per tail vertex and adds one new instance per head
// vertex. An instance is consumed at most once along a history, so no extended vertex gets two
// outgoing hyperarcs within one history. The search starts with the heads of the source hyperarc and
// succeeds when the sink hyperarc is applicable (and allowed).
//
// The extended hypergraph is a tree of histories: an extended hyperarc is one application of a
// hyperarc in one history (a search node); sibling branches may consume the same parent instance.
//
// Both algorithms memoise visited states (the sorted frontier multiset of vertex ids, plus which
// "history-relevant" vertices have appeared, see HyperpathSearchParams::historyRelevant), so a state is
// never explored twice and the search ends on every finite state space. The state space is finite when
// no sequence of hyperarcs can grow the frontier without bound (true for task hypergraphs, where each
// robot and object has exactly one instance); otherwise maxDepth, the budget or the deadline ends it.
//
// Cost per step: applicability is kept per hyperarc as a count of tail vertices missing from the
// frontier (the partial hyperarcs), updated only for the outgoing hyperarcs of a vertex whose last
// instance leaves or whose first instance enters the frontier; successors are judged (duplicate
// test, heuristic) from the current state's key without being applied.
#include <concepts>
#include <cstddef>
#include <functional>
#include <limits>
#include <span>
#include <string_view>
#include <vector>

#include "engine/core/deadline.h"
#include "engine/core/ids.h"
#include "engine/hypergraph/hypergraph_topology.h"

namespace dash {

struct ExtendedVertexTag {};
struct ExtendedHyperarcTag {};
/// A vertex instance: a hypergraph vertex plus the history that produced it (v_TE = <v_T, Pi>).
using ExtendedVertexId = StrongId<ExtendedVertexTag>;
/// One application of a hyperarc in one history (E_TE = <Tail, Head, E_T>); also a search node.
using ExtendedHyperarcId = StrongId<ExtendedHyperarcTag>;

namespace detail {
class SearchWorkspace;
}

enum class HyperpathAlgorithm {
  kGreedy,     // depth-first, successors by increasing priority, backtracking (the authors' greedy query)
  kBestFirst,  // best-first over states by f = g + h: Dijkstra without costToGo, A*-like with it
};

/// The default greedy order (when HyperpathSearchParams::priority is empty), lowest first.
enum class GreedyPriority {
  kHeadCostToGo,      // arcCost(a) + max over head(a) of costToGo: the authors' greedy query
  kCostToGoDecrease,  // arcCost(a) + max over head(a) - max over tail(a) of costToGo: prefers steps
                      // that make progress
};

/// h(state) for kBestFirst, from costToGo over the frontier instances.
enum class FrontierHeuristic {
  kMax,  // max over the frontier: admissible when costToGo is (robots work in parallel)
  kSum,  // sum over the frontier: better informed, not admissible in general
};

enum class HyperpathStatus {
  kFound,
  kExhausted,  // every reachable state explored: no hyperpath (given `allowed`)
  kDeadline,   // the deadline expired or a stop was requested
  kBudget,     // maxExpansions reached, or maxDepth cut states off (so exhaustion proves nothing)
};
std::string_view toString(HyperpathStatus status);

struct HyperpathQuery {
  HyperarcId source;  // its head vertices are the start frontier; its tail is ignored
  HyperarcId sink;    // the goal: reached when its whole tail is on the frontier
};

/// Read-only view of the current search state, passed to the hooks. Valid only during the call.
class HyperpathState {
 public:
  explicit HyperpathState(const detail::SearchWorkspace& workspace) : workspace_(workspace) {}

  const HypergraphTopology& topology() const;
  /// Instances of v on the frontier.
  std::size_t frontierCount(VertexId v) const;
  bool inFrontier(VertexId v) const { return frontierCount(v) > 0; }
  /// Instances of v created along the history so far (start frontier included, consumed or not).
  std::size_t historyCount(VertexId v) const;
  bool inHistory(VertexId v) const { return historyCount(v) > 0; }
  /// The frontier instances, in no particular order.
  std::span<const ExtendedVertexId> frontier() const;
  VertexId vertexOf(ExtendedVertexId instance) const;
  /// Hyperarcs applied so far, source first (walks the history: O(depth)).
  std::vector<HyperarcId> historyHyperarcs() const;
  /// The extended hyperarc (search node) that produced the current state; the root is the source.
  ExtendedHyperarcId node() const;
  /// Steps after the source.
  std::size_t depth() const;
  /// Sum of arcCost over the history.
  double cost() const;

 private:
  const detail::SearchWorkspace& workspace_;
};

/// Passed to onExtendedVertex once per created extended vertex.
struct ExtendedVertex {
  ExtendedVertexId id;
  VertexId vertex;
  ExtendedHyperarcId producedBy;
};

/// Passed to onExtendedHyperarc once per created extended hyperarc (after its head's vertices).
/// The spans are valid only during the call.
struct ExtendedHyperarc {
  ExtendedHyperarcId id;
  ExtendedHyperarcId parent;  // invalid for the root (the source hyperarc)
  HyperarcId hyperarc;
  std::span<const ExtendedVertexId> consumed;  // consumed[i] is an instance of tail[i]
  std::span<const ExtendedVertexId> produced;  // produced[j] is the instance of head[j]
  std::size_t depth = 0;
  double cost = 0.0;  // g after this step
  bool reachesSink = false;
};

using HyperarcFilter = std::function<bool(const HyperpathState&, HyperarcId)>;

/// Settings and hooks (OMPL style: empty std::function = default). The hooks are called from the
/// searching thread only. costToGo and arcCost are cached per element: they must not change during
/// one search.
struct HyperpathSearchParams {
  HyperpathAlgorithm algorithm = HyperpathAlgorithm::kGreedy;
  /// May this hyperarc be expanded from this state? Empty: always. Applied to the sink too.
  HyperarcFilter allowed;
  /// Vertices whose presence in the history `allowed` depends on (history constraints' `pre`): the
  /// state key includes which of them have appeared, so states with equal frontiers but different
  /// relevant histories are told apart. Evaluated once per vertex. Empty: none.
  std::function<bool(VertexId)> historyRelevant;
  /// Estimated cost to reach the goal from a vertex, >= 0. Empty: 0. Infinity marks a vertex from
  /// which the goal cannot be reached: neither search expands into it.
  std::function<double(VertexId)> costToGo;
  /// Cost of applying a hyperarc, >= 0 (negative throws InputError). Empty: 1.
  std::function<double(HyperarcId)> arcCost;
  /// Greedy order, lowest first. Empty: by greedyPriority, and (as in the authors' query) a step
  /// that undoes finished work (whole tail at costToGo 0, some head vertex above 0: an object
  /// lifted from its goal) comes after every other. Ties go to the lower hyperarc id. An infinite
  /// priority drops the hyperarc.
  std::function<double(const HyperpathState&, HyperarcId)> priority;
  GreedyPriority greedyPriority = GreedyPriority::kHeadCostToGo;
  FrontierHeuristic heuristic = FrontierHeuristic::kMax;
  /// f = g + heuristicWeight * h in kBestFirst (1: A*; > 1: weighted A*).
  double heuristicWeight = 1.0;
  Deadline deadline;
  /// States expanded (successors generated) at most.
  std::size_t maxExpansions = std::numeric_limits<std::size_t>::max();
  /// Steps after the source at most (a guard for hypergraphs whose frontier can grow without bound).
  std::size_t maxDepth = std::numeric_limits<std::size_t>::max();
  /// kGreedy: successors waiting to be tried, summed over the depth-first stack, at most (a memory
  /// guard: a deep search with many successors per state keeps them all); past it, kBudget.
  std::size_t maxPendingSuccessors = std::numeric_limits<std::size_t>::max();
  std::function<void(const ExtendedVertex&)> onExtendedVertex;
  std::function<void(const ExtendedHyperarc&)> onExtendedHyperarc;
};

struct HyperpathStep {
  HyperarcId hyperarc;
  ExtendedHyperarcId extended;             // as announced to onExtendedHyperarc
  std::vector<ExtendedVertexId> consumed;  // consumed[i] is an instance of tail(hyperarc)[i]
  std::vector<ExtendedVertexId> produced;  // produced[j] is the instance of head(hyperarc)[j]
  std::vector<std::size_t> dependsOn;      // earlier steps that produced consumed instances (sorted)
};

struct HyperpathStats {
  std::size_t expansions = 0;       // states whose successors were generated
  std::size_t backtracks = 0;       // greedy: states abandoned after all successors failed
  std::size_t statesVisited = 0;    // distinct states stored in the memo table
  std::size_t duplicates = 0;       // successors skipped: their state was already visited
  std::size_t pruned = 0;           // applicable hyperarcs rejected by `allowed` or an infinite cost
  std::size_t depthCutoffs = 0;     // states not expanded because of maxDepth
  std::size_t extendedVertices = 0;
  std::size_t extendedHyperarcs = 0;
  std::size_t maxDepthReached = 0;
  double seconds = 0.0;
};

struct HyperpathResult {
  HyperpathStatus status = HyperpathStatus::kExhausted;
  /// Only when found: steps.front() is the source (consumes nothing, produces the start frontier),
  /// steps.back() the sink. A step depends on the steps listed in dependsOn and on nothing else:
  /// that is the partial order for parallel execution.
  std::vector<HyperpathStep> steps;
  double cost = 0.0;  // sum of arcCost over the steps after the source
  HyperpathStats stats;

  bool found() const { return status == HyperpathStatus::kFound; }
};

/// Searches `graph` for a hyperpath from query.source to query.sink. Returns promptly when the
/// deadline expires. Throws InputError on a bad query (unknown hyperarcs) or a negative cost.
HyperpathResult findHyperpath(const HypergraphTopology& graph, const HyperpathQuery& query,
                              const HyperpathSearchParams& params = {});

/// Convenience for Hypergraph<V, H> (anything with topology()).
template <class Graph>
  requires requires(const Graph& g) { { g.topology() } -> std::convertible_to<const HypergraphTopology&>; }
HyperpathResult findHyperpath(const Graph& graph, const HyperpathQuery& query,
                              const HyperpathSearchParams& params = {}) {
  return findHyperpath(graph.topology(), query, params);
}

/// Both filters must allow; an empty filter allows everything.
HyperarcFilter allOf(HyperarcFilter first, HyperarcFilter second);

}  // namespace dash
