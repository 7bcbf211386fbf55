#include "engine/task/task_query.h"

#include <limits>

#include "engine/task/plan_shortcut.h"

namespace dash {

namespace {

// Greedy order, lowest first. Lexicographic in effect (the weights keep the levels apart):
//  1. actions that would re-block a required element (a constraint's v_pre placed while its v_post
//     is still missing from the frontier) last;
//  2. objects already in a hand before new picks, so at most one object waits on a free hand and
//     the greedy search cannot lock robots that each wait for another's hand; among picks, those that
//     move a blocking object out of the way first;
//     picks of an object whose goal must wait for another object's (a required history constraint:
//     it would block that goal) after all other picks, so that it does not occupy a hand meanwhile;
//  3. the regret of the action against the object's best remaining route (0 on a best route);
//  4. shorter remaining routes first.
constexpr double kReblockPenalty = 1e6;
constexpr double kPickPenalty = 1e4;
constexpr double kUnblockingPickPenalty = 5e3;
constexpr double kWaitingPickPenalty = 1e5;
constexpr double kRemainingWeight = 1e-3;

class TaskGreedyOrder {
 public:
  TaskGreedyOrder(const TaskHypergraph& graph, const TaskSpace& space, const TaskConstraintSet& constraints,
                 const TaskHeuristic& heuristic)
      : graph_(graph.graph()), constraints_(constraints), heuristic_(heuristic) {
    required_.assign(graph_.vertexCount(), 0);
    for (VertexId v : graph_.tail(graph.sink())) required_[v.value()] = 1;
    pending_tasks_of_object_.resize(static_cast<std::size_t>(space.objectCount()));
    const Scene& scene = space.scene();
    for (int k = 0; k < static_cast<int>(scene.tasks.size()); ++k) {
      const int lid = scene.tasks[k].requires_removed_object;
      if (lid < 0) continue;
      if (auto v = graph.find(TaskElement::taskState(k, false))) pending_tasks_of_object_[lid].push_back(*v);
    }
    for (int o = 0; o < space.objectCount(); ++o) {
      const auto v = space.goalLocation(o) >= 0 ? graph.find(TaskElement::objectAt(o, space.goalLocation(o))) : std::nullopt;
      goal_vertex_.push_back(v.value_or(VertexId()));
    }
  }

  double operator()(const HyperpathState& state, HyperarcId a) const {
    const TaskArc& arc = graph_.property(a);
    if (arc.type == TaskArcType::kSink) return -std::numeric_limits<double>::max();
    if (arc.type == TaskArcType::kInspect) return -1e12;
    const TaskHeuristic::ObjectMove move = heuristic_.objectMove(a);
    if (!move.valid) return 0.0;
    bool away = false;
    for (VertexId pending : pending_tasks_of_object_[arc.object]) away = away || state.inFrontier(pending);
    auto cost = [&](VertexId v) { return away ? heuristic_.costAway(v) : heuristic_.costToGo(v); };
    const double regret = arc.cost + cost(move.to) - cost(move.from);

    int reblocks = 0;
    for (VertexId h : graph_.head(a))
      constraints_.forEachOnPre(h, [&](const TaskConstraint& c) {
        if (c.kind != TaskConstraint::Kind::kInteraction && required_[c.post.value()] && !state.inFrontier(c.post))
          ++reblocks;
      });
    double level = reblocks * kReblockPenalty;
    if (arc.type == TaskArcType::kPick) {
      bool unblocks = false;
      for (VertexId t : graph_.tail(a))
        constraints_.forEachOnPre(t, [&](const TaskConstraint& c) {
          if (c.kind == TaskConstraint::Kind::kFrontier && !state.inFrontier(c.post)) unblocks = true;
        });
      bool waits = false;
      const VertexId goal = goal_vertex_[arc.object];
      if (goal.valid())
        constraints_.forEachOnPre(goal, [&](const TaskConstraint& c) {
          if (c.kind == TaskConstraint::Kind::kHistory && c.post_required && !state.inHistory(c.post)) waits = true;
        });
      level += waits ? kWaitingPickPenalty : unblocks ? kUnblockingPickPenalty : kPickPenalty;
    }
    return level + regret + kRemainingWeight * cost(move.to);
  }

 private:
  const TaskGraph& graph_;
  const TaskConstraintSet& constraints_;
  const TaskHeuristic& heuristic_;
  std::vector<char> required_;
  std::vector<std::vector<VertexId>> pending_tasks_of_object_;
  std::vector<VertexId> goal_vertex_;  ///< per object, invalid if it has no goal
};

TaskPlan planFromHyperpath(const TaskHypergraph& graph, const HyperpathResult& result) {
  TaskPlan plan;
  // steps.front() is the source and steps.back() the sink; renumber the rest from 0.
  const std::size_t n = result.steps.size();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const HyperpathStep& s = result.steps[i];
    TaskStep step{s.hyperarc, graph.graph().property(s.hyperarc), {}};
    for (std::size_t d : s.dependsOn)
      if (d >= 1 && d + 1 < n) step.after.push_back(static_cast<int>(d - 1));
    plan.steps.push_back(std::move(step));
  }
  return plan;
}

}  // namespace

TaskQueryResult queryTaskPlan(const TaskHypergraph& graph, const TaskSpace& space,
                              const TaskConstraintSet& constraints, const TaskQueryParams& params,
                              const Deadline& deadline, const TaskQueryObserver& observer) {
  const TaskHeuristic heuristic(graph, space, [&](HyperarcId a) {
    return constraints.forbidsInteraction(a, graph.graph().property(a));
  });
  // The heuristic's routes are a relaxation (robots and frontier/history constraints ignored): an object
  // without one has no plan at all, which the search would find out only by exhausting its budget.
  for (int o = 0; o < space.objectCount(); ++o) {
    const auto start = graph.find(TaskElement::objectAt(o, space.startLocation(o)));
    if (start && heuristic.costToGo(*start) >= TaskHeuristic::kUnreachable) {
      TaskQueryResult out;
      out.status = HyperpathStatus::kExhausted;
      out.unroutable_object = o;
      return out;
    }
  }
  const TaskGreedyOrder priority(graph, space, constraints, heuristic);
  HyperpathSearchParams search;
  search.algorithm = params.algorithm;
  search.allowed = constraints.filter(graph.graph());
  search.historyRelevant = [&](VertexId v) { return constraints.historyRelevant(v); };
  search.costToGo = [&](VertexId v) { return heuristic.costToGo(v); };
  search.arcCost = [&](HyperarcId a) { return graph.graph().property(a).cost; };
  search.priority = [&](const HyperpathState& state, HyperarcId a) { return priority(state, a); };
  search.deadline = deadline;
  search.maxExpansions = params.max_expansions;
  search.onExtendedVertex = observer.onVertex;
  search.onExtendedHyperarc = observer.onHyperarc;

  const HyperpathResult result = findHyperpath(graph.graph(), {graph.source(), graph.sink()}, search);
  TaskQueryResult out;
  out.status = result.status;
  out.stats = result.stats;
  if (result.found()) {
    out.plan = planFromHyperpath(graph, result);
    if (params.remove_round_trips) out.plan = removeRoundTrips(out.plan, graph, constraints);
  }
  return out;
}

}  // namespace dash
