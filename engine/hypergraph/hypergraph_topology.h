#pragma once
// The structure of a directed hypergraph without properties: tail and head sets per hyperarc and
// incoming/outgoing hyperarc lists per vertex. Hypergraph<V, H> wraps it with properties and
// deduplication; the hyperpath search reads only this part, so it is compiled once, not per property.
#include <cstdint>
#include <span>
#include <vector>

#include "engine/core/ids.h"

namespace dash {

struct VertexTag {};
struct HyperarcTag {};
/// A vertex of a Hypergraph (task space element in H_T, motion vertex in H_M).
using VertexId = StrongId<VertexTag>;
/// A hyperarc of a Hypergraph.
using HyperarcId = StrongId<HyperarcTag>;

/// Vertices and hyperarcs in vectors indexed by id. Tail and head are sets: stored sorted by id and
/// without repeats. Value type: copyable and movable. Const members are thread safe.
class HypergraphTopology {
 public:
  /// Adds a vertex with no hyperarcs; its id is the previous vertexCount().
  VertexId addVertex();
  /// Adds a hyperarc; tail and head must already be canonical (see canonicalise) and name existing
  /// vertices. Duplicates are not detected here (Hypergraph does that).
  HyperarcId addHyperarc(std::span<const VertexId> tail, std::span<const VertexId> head);

  std::size_t vertexCount() const { return outgoing_.size(); }
  std::size_t hyperarcCount() const { return arcs_.size(); }
  bool contains(VertexId v) const { return v.valid() && v.value() < vertexCount(); }
  bool contains(HyperarcId a) const { return a.valid() && a.value() < hyperarcCount(); }

  /// Sorted, without repeats.
  std::span<const VertexId> tail(HyperarcId a) const;
  /// Sorted, without repeats.
  std::span<const VertexId> head(HyperarcId a) const;
  /// Hyperarcs whose tail contains v, in insertion order.
  std::span<const HyperarcId> outgoing(VertexId v) const;
  /// Hyperarcs whose head contains v, in insertion order.
  std::span<const HyperarcId> incoming(VertexId v) const;

  void clear();
  void reserve(std::size_t vertices, std::size_t hyperarcs);

  /// Sorts and removes repeats: the canonical form of a tail or head set.
  static void canonicalise(std::vector<VertexId>& set);

 private:
  struct Arc {
    std::uint32_t begin = 0;  // into ends_: tail first, then head
    std::uint32_t tailSize = 0;
    std::uint32_t headSize = 0;
  };
  std::vector<Arc> arcs_;
  std::vector<VertexId> ends_;
  std::vector<std::vector<HyperarcId>> outgoing_;
  std::vector<std::vector<HyperarcId>> incoming_;
};

}  // namespace dash
