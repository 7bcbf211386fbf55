#include "engine/hypergraph/search_workspace.h"

#include <algorithm>
#include <string>
#include <unordered_map>

#include "engine/core/check.h"

namespace dash::detail {
namespace {

constexpr std::uint32_t kNotApplicable = std::numeric_limits<std::uint32_t>::max();
constexpr std::uint64_t kHistorySalt = 0xd6e8feb86659fd93ULL;

// splitmix64 finaliser: spreads vertex ids so that the additive multiset hash has few collisions.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

bool notComputed(double x) { return std::isnan(x); }

/// A cost cached per element: `callback(id)` on first use (`fallback` without a callback), which must
/// be >= 0 and not NaN (`name` says which callback broke that).
template <class Callback, class Id>
double cachedCost(double& cached, const Callback& callback, Id id, double fallback, const char* name) {
  if (notComputed(cached)) {
    cached = callback ? callback(id) : fallback;
    DASH_THROW_UNLESS(cached >= 0.0, std::string("hyperpath search: ") + name + " must be >= 0 (and not NaN)");
  }
  return cached;
}

}  // namespace

// ---------------------------------------------------------------- StateTable

std::uint32_t StateTable::find(std::uint64_t hash, std::span<const std::uint32_t> key) const {
  auto [first, last] = byHash_.equal_range(hash);
  for (auto it = first; it != last; ++it) {
    const Entry& e = entries_[it->second];
    if (e.length == key.size() &&
        std::equal(key.begin(), key.end(), pool_.begin() + static_cast<std::ptrdiff_t>(e.offset)))
      return it->second;
  }
  return kNone;
}

StateTable::Lookup StateTable::insert(std::uint64_t hash, std::span<const std::uint32_t> key) {
  if (const std::uint32_t found = find(hash, key); found != kNone) return {found, false};
  DASH_DEMAND_MSG(entries_.size() < kNone, "too many search states");
  const auto index = static_cast<std::uint32_t>(entries_.size());
  entries_.push_back({pool_.size(), static_cast<std::uint32_t>(key.size())});
  pool_.insert(pool_.end(), key.begin(), key.end());
  byHash_.emplace(hash, index);
  return {index, true};
}

// ---------------------------------------------------------------- SearchWorkspace

SearchWorkspace::SearchWorkspace(const HypergraphTopology& graph, const HyperpathQuery& query,
                                 const HyperpathSearchParams& params, HyperpathStats& stats)
    : graph_(graph), query_(query), params_(params), stats_(stats) {
  DASH_THROW_UNLESS(graph.contains(query.source), "hyperpath query: unknown source hyperarc");
  DASH_THROW_UNLESS(graph.contains(query.sink), "hyperpath query: unknown sink hyperarc");
  DASH_THROW_UNLESS(params.heuristicWeight >= 0.0, "hyperpath search: heuristicWeight must be >= 0");
  const std::size_t vertices = graph.vertexCount();
  const std::size_t arcs = graph.hyperarcCount();
  const double unknown = std::numeric_limits<double>::quiet_NaN();
  instancesOf_.resize(vertices);
  historyCount_.assign(vertices, 0);
  historyRelevant_.assign(vertices, 0);
  costToGo_.assign(vertices, unknown);
  if (params.historyRelevant) {
    for (std::uint32_t v = 0; v < vertices; ++v) {
      if (params.historyRelevant(VertexId(v))) {
        historyRelevant_[v] = 1;
        historyRelevantList_.push_back(VertexId(v));
      }
    }
  }
  missing_.resize(arcs);
  for (std::uint32_t a = 0; a < arcs; ++a)
    missing_[a] = static_cast<std::uint32_t>(graph.tail(HyperarcId(a)).size());
  applicablePos_.assign(arcs, kNotApplicable);
  arcCost_.assign(arcs, unknown);
  priority_.assign(arcs, unknown);
  undoes_.assign(arcs, -1);
  createRoot();
}

void SearchWorkspace::createRoot() {
  const ExtendedHyperarcId root(0);
  SearchNode node;
  node.hyperarc = query_.source;
  node.producedBegin = 0;
  for (VertexId v : graph_.head(query_.source)) {
    const ExtendedVertexId i(static_cast<std::uint32_t>(instances_.size()));
    instances_.push_back({v, root});
    addToFrontier(i);
    addToHistory(v);
  }
  current_ = root;
  const SuccessorKey key = successorKey(HyperarcId());
  node.state = states_.insert(key.hash, key.key).index;
  nodes_.push_back(node);
  ++stats_.extendedHyperarcs;
  stats_.extendedVertices += instances_.size();
  announce(root);
}

bool SearchWorkspace::sinkApplicable() const {
  return graph_.tail(query_.sink).empty() || missing_[query_.sink.value()] == 0;
}

void SearchWorkspace::refreshCurrentKey() {
  if (currentKeyValid_) return;
  currentFrontierKey_.clear();
  for (ExtendedVertexId i : frontier_) currentFrontierKey_.push_back(instances_[i.value()].vertex.value());
  std::sort(currentFrontierKey_.begin(), currentFrontierKey_.end());
  currentHistoryKey_.clear();
  for (VertexId v : historyRelevantList_)
    if (historyCount_[v.value()] > 0) currentHistoryKey_.push_back(v.value());
  currentKeyValid_ = true;
}

SuccessorKey SearchWorkspace::successorKey(HyperarcId arc) {
  refreshCurrentKey();
  const std::span<const VertexId> tail = arc.valid() ? graph_.tail(arc) : std::span<const VertexId>();
  const std::span<const VertexId> head = arc.valid() ? graph_.head(arc) : std::span<const VertexId>();
  std::uint64_t frontierHash = frontierHash_;
  std::uint64_t historyHash = historyHash_;
  for (VertexId v : tail) frontierHash -= mix(v.value());
  for (VertexId v : head) frontierHash += mix(v.value());

  // Frontier: the current multiset less one instance per tail vertex, merged with the head.
  keyScratch_.clear();
  keyScratch_.push_back(0);
  const auto& cur = currentFrontierKey_;
  std::size_t i = 0, t = 0, h = 0;
  while (i < cur.size() || h < head.size()) {
    if (i < cur.size() && t < tail.size()) {
      DASH_DEMAND_MSG(tail[t].value() >= cur[i], "successor of a hyperarc whose tail is not on the frontier");
      if (tail[t].value() == cur[i]) {
        ++i;
        ++t;
        continue;
      }
    }
    if (h < head.size() && (i == cur.size() || head[h].value() <= cur[i])) {
      keyScratch_.push_back(head[h++].value());
    } else {
      keyScratch_.push_back(cur[i++]);
    }
  }
  DASH_DEMAND_MSG(t == tail.size(), "successor of a hyperarc whose tail is not on the frontier");
  keyScratch_[0] = static_cast<std::uint32_t>(keyScratch_.size() - 1);

  // History: the relevant vertices seen so far, merged with the relevant head vertices new to it.
  const auto& seen = currentHistoryKey_;
  std::size_t s = 0;
  for (VertexId v : head) {
    if (!historyRelevant_[v.value()] || historyCount_[v.value()] > 0) continue;
    historyHash += mix(v.value() ^ kHistorySalt);
    while (s < seen.size() && seen[s] < v.value()) keyScratch_.push_back(seen[s++]);
    keyScratch_.push_back(v.value());
  }
  while (s < seen.size()) keyScratch_.push_back(seen[s++]);
  return {keyScratch_, mix(frontierHash ^ mix(historyHash))};
}

double SearchWorkspace::heuristic(std::span<const std::uint32_t> key) {
  double h = 0.0;
  for (std::uint32_t k = 1; k <= key[0]; ++k) {
    const double c = costToGo(VertexId(key[k]));
    h = params_.heuristic == FrontierHeuristic::kMax ? std::max(h, c) : h + c;
  }
  return h;
}

ExtendedHyperarcId SearchWorkspace::addChild(HyperarcId arc, std::uint32_t state) {
  DASH_DEMAND_MSG(nodes_.size() < ExtendedHyperarcId::kInvalid, "too many extended hyperarcs");
  const ExtendedHyperarcId id(static_cast<std::uint32_t>(nodes_.size()));
  const SearchNode& parent = nodes_[current_.value()];
  SearchNode node;
  node.parent = current_;
  node.hyperarc = arc;
  node.depth = parent.depth + 1;
  node.cost = parent.cost + arcCost(arc);
  node.reachesSink = arc == query_.sink;
  node.state = state;
  node.consumedBegin = static_cast<std::uint32_t>(consumedPool_.size());
  for (VertexId v : graph_.tail(arc)) {
    DASH_DEMAND_MSG(!instancesOf_[v.value()].empty(), "hyperarc applied with its tail not on the frontier");
    // The oldest instance: deterministic, and any instance of v leads to the same state.
    consumedPool_.push_back(instancesOf_[v.value()].front());
    ++node.consumedCount;
  }
  node.producedBegin = static_cast<std::uint32_t>(instances_.size());
  for (VertexId v : graph_.head(arc)) {
    DASH_DEMAND_MSG(instances_.size() < ExtendedVertexId::kInvalid, "too many extended vertices");
    instances_.push_back({v, id});
  }
  nodes_.push_back(node);
  ++stats_.extendedHyperarcs;
  stats_.extendedVertices += graph_.head(arc).size();
  stats_.maxDepthReached = std::max<std::size_t>(stats_.maxDepthReached, node.depth);
  announce(id);
  return id;
}

void SearchWorkspace::enter(ExtendedHyperarcId child) {
  const SearchNode& node = nodes_[child.value()];
  DASH_DEMAND(node.parent == current_);
  for (std::uint32_t k = 0; k < node.consumedCount; ++k) removeFromFrontier(consumedPool_[node.consumedBegin + k]);
  const auto head = graph_.head(node.hyperarc);
  for (std::size_t j = 0; j < head.size(); ++j) {
    addToFrontier(ExtendedVertexId(node.producedBegin + static_cast<std::uint32_t>(j)));
    addToHistory(head[j]);
  }
  current_ = child;
  currentKeyValid_ = false;
}

void SearchWorkspace::undo() {
  const SearchNode& node = nodes_[current_.value()];
  DASH_DEMAND_MSG(node.parent.valid(), "cannot undo the root");
  const auto head = graph_.head(node.hyperarc);
  for (std::size_t j = head.size(); j-- > 0;) {
    removeFromHistory(head[j]);
    removeFromFrontier(ExtendedVertexId(node.producedBegin + static_cast<std::uint32_t>(j)));
  }
  for (std::uint32_t k = node.consumedCount; k-- > 0;) addToFrontier(consumedPool_[node.consumedBegin + k]);
  current_ = node.parent;
  currentKeyValid_ = false;
}

void SearchWorkspace::moveTo(ExtendedHyperarcId target) {
  pathScratch_.clear();
  ExtendedHyperarcId b = target;
  while (nodes_[current_.value()].depth > nodes_[b.value()].depth) undo();
  while (nodes_[b.value()].depth > nodes_[current_.value()].depth) {
    pathScratch_.push_back(b);
    b = nodes_[b.value()].parent;
  }
  while (current_ != b) {
    undo();
    pathScratch_.push_back(b);
    b = nodes_[b.value()].parent;
  }
  for (auto it = pathScratch_.rbegin(); it != pathScratch_.rend(); ++it) enter(*it);
}

void SearchWorkspace::addToFrontier(ExtendedVertexId i) {
  Instance& instance = instances_[i.value()];
  const VertexId v = instance.vertex;
  auto& list = instancesOf_[v.value()];
  list.insert(std::lower_bound(list.begin(), list.end(), i), i);
  instance.frontierPos = static_cast<std::uint32_t>(frontier_.size());
  frontier_.push_back(i);
  frontierHash_ += mix(v.value());
  if (list.size() == 1) {
    for (HyperarcId a : graph_.outgoing(v))
      if (--missing_[a.value()] == 0) setApplicable(a, true);
  }
}

void SearchWorkspace::removeFromFrontier(ExtendedVertexId i) {
  const Instance& instance = instances_[i.value()];
  const VertexId v = instance.vertex;
  auto& list = instancesOf_[v.value()];
  const auto it = std::lower_bound(list.begin(), list.end(), i);
  DASH_DEMAND_MSG(it != list.end() && *it == i, "instance is not on the frontier");
  list.erase(it);
  const ExtendedVertexId moved = frontier_.back();
  frontier_[instance.frontierPos] = moved;
  instances_[moved.value()].frontierPos = instance.frontierPos;
  frontier_.pop_back();
  frontierHash_ -= mix(v.value());
  if (list.empty()) {
    for (HyperarcId a : graph_.outgoing(v))
      if (missing_[a.value()]++ == 0) setApplicable(a, false);
  }
}

void SearchWorkspace::addToHistory(VertexId v) {
  if (historyCount_[v.value()]++ == 0 && historyRelevant_[v.value()]) historyHash_ += mix(v.value() ^ kHistorySalt);
}

void SearchWorkspace::removeFromHistory(VertexId v) {
  if (--historyCount_[v.value()] == 0 && historyRelevant_[v.value()]) historyHash_ -= mix(v.value() ^ kHistorySalt);
}

void SearchWorkspace::setApplicable(HyperarcId a, bool on) {
  std::uint32_t& pos = applicablePos_[a.value()];
  if (on) {
    pos = static_cast<std::uint32_t>(applicable_.size());
    applicable_.push_back(a);
  } else {
    const HyperarcId moved = applicable_.back();
    applicable_[pos] = moved;
    applicablePos_[moved.value()] = pos;
    applicable_.pop_back();
    pos = kNotApplicable;
  }
}

double SearchWorkspace::arcCost(HyperarcId a) {
  return cachedCost(arcCost_[a.value()], params_.arcCost, a, 1.0, "arcCost");
}

double SearchWorkspace::costToGo(VertexId v) {
  return cachedCost(costToGo_[v.value()], params_.costToGo, v, 0.0, "costToGo");
}

double SearchWorkspace::defaultPriority(HyperarcId a) {
  double& cached = priority_[a.value()];
  if (notComputed(cached)) {
    double head = 0.0, tail = 0.0;
    for (VertexId v : graph_.head(a)) head = std::max(head, costToGo(v));
    cached = arcCost(a) + head;
    if (params_.greedyPriority == GreedyPriority::kCostToGoDecrease) {
      for (VertexId v : graph_.tail(a)) tail = std::max(tail, costToGo(v));
      cached -= tail;  // inf - inf is NaN: dropped like an infinite priority
    }
  }
  return cached;
}

bool SearchWorkspace::undoesFinishedWork(HyperarcId a) {
  std::int8_t& cached = undoes_[a.value()];
  if (cached < 0) {
    double head = 0.0, tail = 0.0;
    for (VertexId v : graph_.head(a)) head = std::max(head, costToGo(v));
    for (VertexId v : graph_.tail(a)) tail = std::max(tail, costToGo(v));
    cached = tail == 0.0 && head > 0.0 ? 1 : 0;
  }
  return cached == 1;
}

void SearchWorkspace::announce(ExtendedHyperarcId n) {
  if (!params_.onExtendedVertex && !params_.onExtendedHyperarc) return;
  const SearchNode& node = nodes_[n.value()];
  const auto headSize = static_cast<std::uint32_t>(graph_.head(node.hyperarc).size());
  if (params_.onExtendedVertex) {
    for (std::uint32_t j = 0; j < headSize; ++j) {
      const ExtendedVertexId i(node.producedBegin + j);
      params_.onExtendedVertex({i, instances_[i.value()].vertex, n});
    }
  }
  if (params_.onExtendedHyperarc) {
    std::vector<ExtendedVertexId> produced(headSize);
    for (std::uint32_t j = 0; j < headSize; ++j) produced[j] = ExtendedVertexId(node.producedBegin + j);
    params_.onExtendedHyperarc({n, node.parent, node.hyperarc,
                                std::span<const ExtendedVertexId>(consumedPool_.data() + node.consumedBegin,
                                                                  node.consumedCount),
                                produced, node.depth, node.cost, node.reachesSink});
  }
}

std::vector<HyperpathStep> SearchWorkspace::extractSteps(ExtendedHyperarcId last) const {
  std::vector<ExtendedHyperarcId> path;
  for (ExtendedHyperarcId n = last; n.valid(); n = nodes_[n.value()].parent) path.push_back(n);
  std::reverse(path.begin(), path.end());
  std::unordered_map<ExtendedHyperarcId, std::size_t> stepOf;
  for (std::size_t s = 0; s < path.size(); ++s) stepOf.emplace(path[s], s);

  std::vector<HyperpathStep> steps(path.size());
  for (std::size_t s = 0; s < path.size(); ++s) {
    const SearchNode& node = nodes_[path[s].value()];
    HyperpathStep& step = steps[s];
    step.hyperarc = node.hyperarc;
    step.extended = path[s];
    step.consumed.assign(consumedPool_.begin() + node.consumedBegin,
                         consumedPool_.begin() + node.consumedBegin + node.consumedCount);
    const std::size_t headSize = graph_.head(node.hyperarc).size();
    for (std::size_t j = 0; j < headSize; ++j)
      step.produced.push_back(ExtendedVertexId(node.producedBegin + static_cast<std::uint32_t>(j)));
    for (ExtendedVertexId i : step.consumed) {
      const auto producer = stepOf.find(instances_[i.value()].producer);
      DASH_DEMAND_MSG(producer != stepOf.end() && producer->second < s, "consumed an instance not produced earlier");
      step.dependsOn.push_back(producer->second);
    }
    std::sort(step.dependsOn.begin(), step.dependsOn.end());
    step.dependsOn.erase(std::unique(step.dependsOn.begin(), step.dependsOn.end()), step.dependsOn.end());
  }
  return steps;
}

}  // namespace dash::detail

// ---------------------------------------------------------------- HyperpathState

namespace dash {

const HypergraphTopology& HyperpathState::topology() const { return workspace_.graph(); }
std::size_t HyperpathState::frontierCount(VertexId v) const {
  DASH_DEMAND(workspace_.graph().contains(v));
  return workspace_.frontierCount(v);
}
std::size_t HyperpathState::historyCount(VertexId v) const {
  DASH_DEMAND(workspace_.graph().contains(v));
  return workspace_.historyCount(v);
}
std::span<const ExtendedVertexId> HyperpathState::frontier() const { return workspace_.frontier(); }
VertexId HyperpathState::vertexOf(ExtendedVertexId instance) const { return workspace_.vertexOf(instance); }
ExtendedHyperarcId HyperpathState::node() const { return workspace_.current(); }
std::size_t HyperpathState::depth() const { return workspace_.node(workspace_.current()).depth; }
double HyperpathState::cost() const { return workspace_.node(workspace_.current()).cost; }

std::vector<HyperarcId> HyperpathState::historyHyperarcs() const {
  std::vector<HyperarcId> arcs;
  for (ExtendedHyperarcId n = workspace_.current(); n.valid(); n = workspace_.node(n).parent)
    arcs.push_back(workspace_.node(n).hyperarc);
  std::reverse(arcs.begin(), arcs.end());
  return arcs;
}

}  // namespace dash
