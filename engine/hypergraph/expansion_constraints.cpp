#include "engine/hypergraph/expansion_constraints.h"

#include <algorithm>
#include <memory>

#include "engine/core/check.h"

namespace dash {

bool ExpansionConstraints::add(std::unordered_map<VertexId, std::vector<VertexId>>& byPost, VertexId pre,
                               VertexId post) {
  DASH_THROW_UNLESS(pre.valid() && post.valid(), "task constraint with an invalid vertex");
  std::vector<VertexId>& pres = byPost[post];
  if (std::find(pres.begin(), pres.end(), pre) != pres.end()) return false;
  pres.push_back(pre);
  return true;
}

bool ExpansionConstraints::addFrontier(VertexId pre, VertexId post) {
  if (!add(frontierByPost_, pre, post)) return false;
  ++frontierCount_;
  return true;
}

bool ExpansionConstraints::addHistory(VertexId pre, VertexId post) {
  if (!add(historyByPost_, pre, post)) return false;
  historyPre_.insert(pre);
  ++historyCount_;
  return true;
}

bool ExpansionConstraints::allows(const HyperpathState& state, HyperarcId arc) const {
  if (empty()) return true;
  const HypergraphTopology& graph = state.topology();
  const auto tail = graph.tail(arc);
  for (VertexId post : graph.head(arc)) {
    if (auto it = frontierByPost_.find(post); it != frontierByPost_.end()) {
      for (VertexId pre : it->second) {
        if (!graph.contains(pre)) continue;
        const std::size_t consumed = std::binary_search(tail.begin(), tail.end(), pre) ? 1 : 0;
        if (state.frontierCount(pre) > consumed) return false;
      }
    }
    if (auto it = historyByPost_.find(post); it != historyByPost_.end()) {
      for (VertexId pre : it->second)
        if (graph.contains(pre) && state.inHistory(pre)) return false;
    }
  }
  return true;
}

void ExpansionConstraints::clear() {
  frontierByPost_.clear();
  historyByPost_.clear();
  historyPre_.clear();
  frontierCount_ = 0;
  historyCount_ = 0;
}

void ExpansionConstraints::installInto(HyperpathSearchParams& params) const {
  auto self = std::make_shared<const ExpansionConstraints>(*this);
  params.allowed = allOf(std::move(params.allowed), [self](const HyperpathState& state, HyperarcId arc) {
    return self->allows(state, arc);
  });
  auto previous = std::move(params.historyRelevant);
  params.historyRelevant = [self, previous = std::move(previous)](VertexId v) {
    return self->historyRelevant(v) || (previous && previous(v));
  };
}

}  // namespace dash
