#pragma once
// A generic directed hypergraph with properties on vertices and hyperarcs, used for the task space
// hypergraph H_T and the motion hypergraph H_M (DaSH, Motes et al. T-RO 2023; Lazy-DaSH). As in the
// authors' Utilities/Hypergraph.h, a vertex is {id, property} and a hyperarc {id, tail set, head set,
// property}, with incoming and outgoing hyperarc lists per vertex. Adding an element that already
// exists returns the existing id; the lookup goes through a hash of the property (and of the tail and
// head sets for hyperarcs), never a scan.
//
// Requirements: std::hash<P> and operator== for both property types. Properties are immutable once
// added (changing one would break the lookup). Value type: copyable and movable.
#include <algorithm>
#include <cstddef>
#include <functional>
#include <optional>
#include <ranges>
#include <span>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/core/check.h"
#include "engine/hypergraph/hypergraph_topology.h"

namespace dash {

template <class Id>
struct AddResult {
  Id id;
  bool inserted = false;  // false: an equal element existed and id is that element
};

template <class VertexProperty, class HyperarcProperty>
class Hypergraph {
 public:
  using VertexPropertyType = VertexProperty;
  using HyperarcPropertyType = HyperarcProperty;

  /// Adds a vertex, or returns the id of the vertex with an equal property.
  AddResult<VertexId> addVertex(VertexProperty property) {
    const std::size_t key = std::hash<VertexProperty>{}(property);
    if (auto found = findVertex(key, property)) return {*found, false};
    const VertexId id = topology_.addVertex();
    vertexProperties_.push_back(std::move(property));
    vertexIndex_.emplace(key, id);
    return {id, true};
  }

  /// Adds a hyperarc, or returns the id of the hyperarc with the same tail set, head set and an equal
  /// property. Tail and head are sets: order and repeats do not matter. Every vertex must exist
  /// (throws InputError otherwise).
  AddResult<HyperarcId> addHyperarc(std::vector<VertexId> tail, std::vector<VertexId> head,
                                    HyperarcProperty property) {
    canonicaliseChecked(tail);
    canonicaliseChecked(head);
    const std::size_t key = hyperarcKey(tail, head, property);
    if (auto found = findHyperarc(key, tail, head, property)) return {*found, false};
    const HyperarcId id = topology_.addHyperarc(tail, head);
    hyperarcProperties_.push_back(std::move(property));
    hyperarcIndex_.emplace(key, id);
    return {id, true};
  }

  std::optional<VertexId> find(const VertexProperty& property) const {
    return findVertex(std::hash<VertexProperty>{}(property), property);
  }
  std::optional<HyperarcId> find(std::vector<VertexId> tail, std::vector<VertexId> head,
                                 const HyperarcProperty& property) const {
    HypergraphTopology::canonicalise(tail);
    HypergraphTopology::canonicalise(head);
    return findHyperarc(hyperarcKey(tail, head, property), tail, head, property);
  }

  const VertexProperty& property(VertexId v) const {
    DASH_DEMAND(topology_.contains(v));
    return vertexProperties_[v.value()];
  }
  const HyperarcProperty& property(HyperarcId a) const {
    DASH_DEMAND(topology_.contains(a));
    return hyperarcProperties_[a.value()];
  }
  std::span<const VertexId> tail(HyperarcId a) const { return topology_.tail(a); }
  std::span<const VertexId> head(HyperarcId a) const { return topology_.head(a); }
  std::span<const HyperarcId> outgoing(VertexId v) const { return topology_.outgoing(v); }
  std::span<const HyperarcId> incoming(VertexId v) const { return topology_.incoming(v); }

  std::size_t vertexCount() const { return topology_.vertexCount(); }
  std::size_t hyperarcCount() const { return topology_.hyperarcCount(); }
  bool contains(VertexId v) const { return topology_.contains(v); }
  bool contains(HyperarcId a) const { return topology_.contains(a); }

  /// All vertex ids in increasing order: `for (VertexId v : graph.vertices())`.
  auto vertices() const {
    return std::views::iota(VertexId::value_type{0}, static_cast<VertexId::value_type>(vertexCount())) |
           std::views::transform([](VertexId::value_type i) { return VertexId(i); });
  }
  /// All hyperarc ids in increasing order.
  auto hyperarcs() const {
    return std::views::iota(HyperarcId::value_type{0},
                            static_cast<HyperarcId::value_type>(hyperarcCount())) |
           std::views::transform([](HyperarcId::value_type i) { return HyperarcId(i); });
  }

  /// The structure alone, as the hyperpath search reads it.
  const HypergraphTopology& topology() const { return topology_; }

  void clear() {
    topology_.clear();
    vertexProperties_.clear();
    hyperarcProperties_.clear();
    vertexIndex_.clear();
    hyperarcIndex_.clear();
  }
  void reserve(std::size_t vertices, std::size_t hyperarcs) {
    topology_.reserve(vertices, hyperarcs);
    vertexProperties_.reserve(vertices);
    hyperarcProperties_.reserve(hyperarcs);
    vertexIndex_.reserve(vertices);
    hyperarcIndex_.reserve(hyperarcs);
  }

 private:
  void canonicaliseChecked(std::vector<VertexId>& set) const {
    for (VertexId v : set) DASH_THROW_UNLESS(contains(v), "hyperarc names a vertex that does not exist");
    HypergraphTopology::canonicalise(set);
  }

  static std::size_t combine(std::size_t seed, std::size_t value) {
    return seed ^ (value + 0x9e3779b97f4a7c15ULL + (seed << 6) + (seed >> 2));
  }
  static std::size_t hyperarcKey(std::span<const VertexId> tail, std::span<const VertexId> head,
                                 const HyperarcProperty& property) {
    std::size_t seed = std::hash<HyperarcProperty>{}(property);
    seed = combine(seed, tail.size());
    for (VertexId v : tail) seed = combine(seed, v.value());
    seed = combine(seed, head.size());
    for (VertexId v : head) seed = combine(seed, v.value());
    return seed;
  }

  std::optional<VertexId> findVertex(std::size_t key, const VertexProperty& property) const {
    auto [first, last] = vertexIndex_.equal_range(key);
    for (auto it = first; it != last; ++it)
      if (vertexProperties_[it->second.value()] == property) return it->second;
    return std::nullopt;
  }
  std::optional<HyperarcId> findHyperarc(std::size_t key, std::span<const VertexId> tail,
                                         std::span<const VertexId> head,
                                         const HyperarcProperty& property) const {
    auto [first, last] = hyperarcIndex_.equal_range(key);
    for (auto it = first; it != last; ++it) {
      const HyperarcId id = it->second;
      if (std::ranges::equal(topology_.tail(id), tail) && std::ranges::equal(topology_.head(id), head) &&
          hyperarcProperties_[id.value()] == property)
        return id;
    }
    return std::nullopt;
  }

  HypergraphTopology topology_;
  std::vector<VertexProperty> vertexProperties_;
  std::vector<HyperarcProperty> hyperarcProperties_;
  // Keyed on the full hash; equal hashes are told apart by comparing the stored elements, so the
  // properties are stored once.
  std::unordered_multimap<std::size_t, VertexId> vertexIndex_;
  std::unordered_multimap<std::size_t, HyperarcId> hyperarcIndex_;
};

}  // namespace dash
