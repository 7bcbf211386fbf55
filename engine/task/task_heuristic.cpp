#include "engine/task/task_heuristic.h"

#include <queue>

namespace dash {

namespace {

bool isObjectState(const TaskElement& e) {
  return e.kind == ElementKind::kObjectAt || e.kind == ElementKind::kHolding;
}

struct Edge {
  VertexId from;
  double cost;
};

std::vector<double> dijkstraFrom(const std::vector<VertexId>& targets, const std::vector<std::vector<Edge>>& reverse,
                                 std::size_t n) {
  std::vector<double> dist(n, TaskHeuristic::kUnreachable);
  using Item = std::pair<double, std::uint32_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  for (VertexId t : targets) {
    dist[t.value()] = 0.0;
    open.emplace(0.0, t.value());
  }
  while (!open.empty()) {
    const auto [d, v] = open.top();
    open.pop();
    if (d > dist[v]) continue;
    for (const Edge& e : reverse[v]) {
      const double nd = d + e.cost;
      if (nd < dist[e.from.value()]) {
        dist[e.from.value()] = nd;
        open.emplace(nd, e.from.value());
      }
    }
  }
  return dist;
}

}  // namespace

TaskHeuristic::TaskHeuristic(const TaskHypergraph& hypergraph, const TaskSpace& space,
                             const std::function<bool(HyperarcId)>& forbidden) {
  const TaskGraph& graph = hypergraph.graph();
  const std::size_t n = graph.vertexCount();
  moves_.resize(graph.hyperarcCount());
  std::vector<std::vector<Edge>> reverse(n);
  for (HyperarcId a : graph.hyperarcs()) {
    const TaskArc& arc = graph.property(a);
    if (arc.type != TaskArcType::kPick && arc.type != TaskArcType::kPlace && arc.type != TaskArcType::kHandover)
      continue;
    ObjectMove move;
    for (VertexId v : graph.tail(a))
      if (isObjectState(graph.property(v))) move.from = v;
    for (VertexId v : graph.head(a))
      if (isObjectState(graph.property(v))) move.to = v;
    move.valid = move.from.valid() && move.to.valid();
    moves_[a.value()] = move;
    if (move.valid && !(forbidden && forbidden(a))) reverse[move.to.value()].push_back({move.from, arc.cost});
  }

  std::vector<VertexId> goal_targets;
  std::vector<VertexId> away_targets;
  std::vector<char> needs_away(static_cast<std::size_t>(space.objectCount()), 0);
  for (const SceneTask& task : space.scene().tasks)
    if (task.requires_removed_object >= 0) needs_away[task.requires_removed_object] = 1;
  for (VertexId v : graph.vertices()) {
    const TaskElement& e = graph.property(v);
    if (e.kind != ElementKind::kObjectAt) continue;
    const int goal = space.goalLocation(e.object);
    if (goal < 0 || goal == e.location) goal_targets.push_back(v);
    if (needs_away[e.object] != 0 && e.location != space.startLocation(e.object)) away_targets.push_back(v);
  }
  to_goal_ = dijkstraFrom(goal_targets, reverse, n);
  const std::vector<double> away = dijkstraFrom(away_targets, reverse, n);
  away_ = to_goal_;
  for (VertexId v : graph.vertices()) {
    const TaskElement& e = graph.property(v);
    if (!isObjectState(e)) {
      to_goal_[v.value()] = 0.0;
      away_[v.value()] = 0.0;
    } else if (needs_away[e.object] != 0) {
      away_[v.value()] = away[v.value()];
    }
  }
}

}  // namespace dash
