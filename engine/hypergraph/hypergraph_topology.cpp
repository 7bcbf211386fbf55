#include "engine/hypergraph/hypergraph_topology.h"

#include <algorithm>
#include <limits>

#include "engine/core/check.h"

namespace dash {

VertexId HypergraphTopology::addVertex() {
  DASH_DEMAND_MSG(vertexCount() < VertexId::kInvalid, "too many hypergraph vertices");
  outgoing_.emplace_back();
  incoming_.emplace_back();
  return VertexId(static_cast<VertexId::value_type>(vertexCount() - 1));
}

HyperarcId HypergraphTopology::addHyperarc(std::span<const VertexId> tail, std::span<const VertexId> head) {
  DASH_DEMAND_MSG(hyperarcCount() < HyperarcId::kInvalid, "too many hyperarcs");
  DASH_DEMAND_MSG(ends_.size() + tail.size() + head.size() <= std::numeric_limits<std::uint32_t>::max(),
                  "hyperarc end storage overflow");
  DASH_DEMAND(std::is_sorted(tail.begin(), tail.end()) && std::is_sorted(head.begin(), head.end()));
  DASH_DEMAND(std::adjacent_find(tail.begin(), tail.end()) == tail.end());
  DASH_DEMAND(std::adjacent_find(head.begin(), head.end()) == head.end());
  const HyperarcId id(static_cast<HyperarcId::value_type>(hyperarcCount()));
  Arc arc{static_cast<std::uint32_t>(ends_.size()), static_cast<std::uint32_t>(tail.size()),
          static_cast<std::uint32_t>(head.size())};
  for (VertexId v : tail) {
    DASH_DEMAND_MSG(contains(v), "hyperarc tail names a vertex that does not exist");
    ends_.push_back(v);
    outgoing_[v.value()].push_back(id);
  }
  for (VertexId v : head) {
    DASH_DEMAND_MSG(contains(v), "hyperarc head names a vertex that does not exist");
    ends_.push_back(v);
    incoming_[v.value()].push_back(id);
  }
  arcs_.push_back(arc);
  return id;
}

std::span<const VertexId> HypergraphTopology::tail(HyperarcId a) const {
  DASH_DEMAND(contains(a));
  const Arc& arc = arcs_[a.value()];
  return {ends_.data() + arc.begin, arc.tailSize};
}

std::span<const VertexId> HypergraphTopology::head(HyperarcId a) const {
  DASH_DEMAND(contains(a));
  const Arc& arc = arcs_[a.value()];
  return {ends_.data() + arc.begin + arc.tailSize, arc.headSize};
}

std::span<const HyperarcId> HypergraphTopology::outgoing(VertexId v) const {
  DASH_DEMAND(contains(v));
  return outgoing_[v.value()];
}

std::span<const HyperarcId> HypergraphTopology::incoming(VertexId v) const {
  DASH_DEMAND(contains(v));
  return incoming_[v.value()];
}

void HypergraphTopology::clear() {
  arcs_.clear();
  ends_.clear();
  outgoing_.clear();
  incoming_.clear();
}

void HypergraphTopology::reserve(std::size_t vertices, std::size_t hyperarcs) {
  outgoing_.reserve(vertices);
  incoming_.reserve(vertices);
  arcs_.reserve(hyperarcs);
}

void HypergraphTopology::canonicalise(std::vector<VertexId>& set) {
  std::sort(set.begin(), set.end());
  set.erase(std::unique(set.begin(), set.end()), set.end());
}

}  // namespace dash
