#pragma once
// Lazy-DaSH task constraints C_T = C_h ∪ C_f (Sec. "Query (Task-extended Hypergraph)"), as a ready
// filter for the hyperpath search. Each constraint is a pair (pre, post) of vertices and restricts
// the expansion of every hyperarc whose head contains post:
//   frontier constraint: pre must not be on the frontier (the instances the hyperarc itself consumes
//                        do not count: they leave the frontier with this step);
//   history constraint:  pre must not have appeared in the history (any instance created so far,
//                        start frontier included, whether consumed or not).
// Constraints chain: a post may be the pre of another pair. Value type: copyable and movable.
#include <cstddef>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "engine/hypergraph/hyperpath_search.h"

namespace dash {

class ExpansionConstraints {
 public:
  /// Returns false when the pair was already there.
  bool addFrontier(VertexId pre, VertexId post);
  bool addHistory(VertexId pre, VertexId post);

  /// True when no constraint forbids expanding `arc` from `state`.
  bool allows(const HyperpathState& state, HyperarcId arc) const;
  /// True for the `pre` of every history constraint (see HyperpathSearchParams::historyRelevant).
  bool historyRelevant(VertexId v) const { return historyPre_.contains(v); }

  std::size_t frontierCount() const { return frontierCount_; }
  std::size_t historyCount() const { return historyCount_; }
  bool empty() const { return frontierCount_ == 0 && historyCount_ == 0; }
  void clear();

  /// Adds these constraints (a copy) to params: `allowed` becomes "the previous filter and these",
  /// `historyRelevant` "the previous predicate or these pres".
  void installInto(HyperpathSearchParams& params) const;

 private:
  static bool add(std::unordered_map<VertexId, std::vector<VertexId>>& byPost, VertexId pre, VertexId post);

  std::unordered_map<VertexId, std::vector<VertexId>> frontierByPost_;  // post -> pres
  std::unordered_map<VertexId, std::vector<VertexId>> historyByPost_;
  std::unordered_set<VertexId> historyPre_;
  std::size_t frontierCount_ = 0;
  std::size_t historyCount_ = 0;
};

}  // namespace dash
