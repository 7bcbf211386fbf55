#pragma once
// Internal to the hyperpath search: the search tree (extended hypergraph), the current state with
// apply/undo, the partial-hyperarc bookkeeping and the memo table of visited states. Not for callers.
//
// Successors are judged without being applied: their state key, hash and heuristic come from the
// current state's sorted key in O(frontier) time, so a duplicate costs no update of the per-hyperarc
// bookkeeping (a robot vertex can be in the tail of thousands of hyperarcs).
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

#include "engine/hypergraph/hyperpath_search.h"

namespace dash::detail {

/// Visited states: the sorted frontier vertex multiset plus the sorted set of history-relevant
/// vertices seen. Stored once each; equal 64-bit hashes are told apart by comparing the keys.
class StateTable {
 public:
  static constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  struct Lookup {
    std::uint32_t index = kNone;
    bool inserted = false;
  };
  /// The index of an equal key, or kNone.
  std::uint32_t find(std::uint64_t hash, std::span<const std::uint32_t> key) const;
  Lookup insert(std::uint64_t hash, std::span<const std::uint32_t> key);
  double& bestCost(std::uint32_t index) { return entries_[index].bestCost; }
  std::size_t size() const { return entries_.size(); }

 private:
  struct Entry {
    std::uint64_t offset = 0;
    std::uint32_t length = 0;
    double bestCost = std::numeric_limits<double>::infinity();
  };
  std::vector<std::uint32_t> pool_;
  std::vector<Entry> entries_;
  std::unordered_multimap<std::uint64_t, std::uint32_t> byHash_;
};

struct SearchNode {
  ExtendedHyperarcId parent;
  HyperarcId hyperarc;
  std::uint32_t depth = 0;
  std::uint32_t consumedBegin = 0;  // into the consumed pool
  std::uint32_t consumedCount = 0;  // tail(hyperarc).size(); 0 for the root (the source's tail is ignored)
  std::uint32_t producedBegin = 0;  // first produced instance; head(hyperarc).size() consecutive ids
  std::uint32_t state = StateTable::kNone;
  double cost = 0.0;
  bool reachesSink = false;
};

/// A successor's state key (in the workspace's scratch buffer, valid until the next call) and hash.
struct SuccessorKey {
  std::span<const std::uint32_t> key;
  std::uint64_t hash = 0;
};

class SearchWorkspace {
 public:
  SearchWorkspace(const HypergraphTopology& graph, const HyperpathQuery& query,
                  const HyperpathSearchParams& params, HyperpathStats& stats);

  const HypergraphTopology& graph() const { return graph_; }
  HyperpathState view() const { return HyperpathState(*this); }

  // --- the current state
  ExtendedHyperarcId current() const { return current_; }
  const SearchNode& node(ExtendedHyperarcId n) const { return nodes_[n.value()]; }
  std::size_t frontierCount(VertexId v) const { return instancesOf_[v.value()].size(); }
  std::size_t historyCount(VertexId v) const { return historyCount_[v.value()]; }
  std::span<const ExtendedVertexId> frontier() const { return frontier_; }
  VertexId vertexOf(ExtendedVertexId i) const { return instances_[i.value()].vertex; }
  /// Hyperarcs whose whole tail is on the frontier (non-empty tails only), in no fixed order.
  std::span<const HyperarcId> applicable() const { return applicable_; }
  bool sinkApplicable() const;
  HyperarcId sink() const { return query_.sink; }
  HyperarcId source() const { return query_.source; }

  // --- successors, judged without applying them
  /// The key of the state that applying `arc` (applicable) to the current state would give.
  SuccessorKey successorKey(HyperarcId arc);
  /// h of a key's frontier (FrontierHeuristic).
  double heuristic(std::span<const std::uint32_t> key);
  StateTable& states() { return states_; }

  // --- the tree
  /// Adds the node "apply `arc` to the current state" (its state index in the memo table, or kNone)
  /// and announces it to the observers; the current state does not change.
  ExtendedHyperarcId addChild(HyperarcId arc, std::uint32_t state);
  /// Applies a child of the current node: it becomes current.
  void enter(ExtendedHyperarcId child);
  /// Undoes the current node's step; its parent becomes current.
  void undo();
  /// Makes `target` current by undoing up to the common ancestor and redoing down.
  void moveTo(ExtendedHyperarcId target);
  /// Steps from the root to `last`, source first.
  std::vector<HyperpathStep> extractSteps(ExtendedHyperarcId last) const;

  // --- costs (cached per element)
  double arcCost(HyperarcId a);
  double costToGo(VertexId v);
  /// The greedy priority of `arc` by params.greedyPriority (state independent, cached).
  double defaultPriority(HyperarcId a);
  /// Does `arc` undo finished work: all its tail at costToGo 0, some of its head above (cached)?
  bool undoesFinishedWork(HyperarcId a);

 private:
  struct Instance {
    VertexId vertex;
    ExtendedHyperarcId producer;
    std::uint32_t frontierPos = 0;
  };
  void createRoot();
  void addToFrontier(ExtendedVertexId i);
  void removeFromFrontier(ExtendedVertexId i);
  void addToHistory(VertexId v);
  void removeFromHistory(VertexId v);
  void setApplicable(HyperarcId a, bool on);
  void refreshCurrentKey();
  void announce(ExtendedHyperarcId n);

  const HypergraphTopology& graph_;
  const HyperpathQuery query_;
  const HyperpathSearchParams& params_;
  HyperpathStats& stats_;

  std::vector<SearchNode> nodes_;
  std::vector<Instance> instances_;
  std::vector<ExtendedVertexId> consumedPool_;
  ExtendedHyperarcId current_;

  std::vector<std::vector<ExtendedVertexId>> instancesOf_;  // per vertex, sorted: the frontier
  std::vector<ExtendedVertexId> frontier_;
  std::vector<std::uint32_t> historyCount_;   // per vertex
  std::vector<std::uint32_t> missing_;        // per hyperarc: tail vertices absent from the frontier
  std::vector<std::uint32_t> applicablePos_;  // per hyperarc: index in applicable_, or none
  std::vector<HyperarcId> applicable_;
  std::vector<char> historyRelevant_;  // per vertex
  std::vector<VertexId> historyRelevantList_;
  std::uint64_t frontierHash_ = 0;  // additive, so a multiset hashes the same in any order
  std::uint64_t historyHash_ = 0;

  // The current state's key, rebuilt lazily after the state changes.
  bool currentKeyValid_ = false;
  std::vector<std::uint32_t> currentFrontierKey_;  // sorted vertex ids, with repeats
  std::vector<std::uint32_t> currentHistoryKey_;   // sorted history-relevant vertices seen
  std::vector<std::uint32_t> keyScratch_;

  std::vector<double> arcCost_;   // NaN: not computed yet
  std::vector<double> costToGo_;  // NaN: not computed yet
  std::vector<double> priority_;  // NaN: not computed yet
  std::vector<std::int8_t> undoes_;  // -1: not computed yet
  std::vector<ExtendedHyperarcId> pathScratch_;
  StateTable states_;
};

}  // namespace dash::detail
