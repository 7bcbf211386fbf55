#include "engine/dash/combined_query.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <unordered_set>

namespace dash {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kOnRoute = 1e-6;  // regret below this: on a cheapest route
// Priority levels (lowest first); regrets and path costs (radians) stay far below the gaps.
constexpr double kPickPenalty = 1e4;
constexpr double kHoldMove = 1e5;
constexpr double kReceiveMove = 2e5;
constexpr double kInspectMove = 2.5e5;
constexpr double kPickMove = 3e5;
constexpr double kDetour = 3.5e5;
constexpr double kHome = 4e5;
constexpr double kUndoMove = 5e5;
constexpr double kUndo = 6e5;
constexpr double kPartnerWaiting = 5e4;  // a handover partner already in place: go there first
constexpr double kIdleMove = 7e5;        // complete pass: a move to where nothing can happen now

using Kind = MotionVertex::Kind;
using Type = MotionArc::Type;

bool isObjectState(const MotionVertex& v) { return v.kind == Kind::kObject || v.kind == Kind::kHolding; }
bool isRobotState(const MotionVertex& v) { return v.kind == Kind::kRobot || v.kind == Kind::kHolding; }
}  // namespace

struct CombinedQuery::Summary {
  ExtendedHyperarcId node;
  bool valid = false;
  std::vector<VertexId> robot_at;  ///< the vertex each robot's instance is at
  int focus = -1;                  ///< the one-object pass: the object it may move now
};

CombinedQuery::CombinedQuery(const MotionHypergraph& graph) : graph_(&graph) { refresh({}); }

std::pair<VertexId, VertexId> CombinedQuery::objectMove(HyperarcId a) const {
  const MotionGraph& g = graph_->graph();
  const MotionArc& arc = g.property(a);
  if (arc.type != Type::kPick && arc.type != Type::kPlace && arc.type != Type::kHandover && arc.type != Type::kMove)
    return {};
  VertexId from, to;
  for (VertexId v : g.tail(a))
    if (isObjectState(g.property(v))) from = v;
  for (VertexId v : g.head(a))
    if (isObjectState(g.property(v))) to = v;
  return {from, to};
}

void CombinedQuery::refresh(const std::vector<HyperarcId>& forbidden_list) {
  const std::unordered_set<HyperarcId> forbidden(forbidden_list.begin(), forbidden_list.end());
  const MotionGraph& g = graph_->graph();
  const TaskSpace& space = graph_->space();
  const Scene& scene = space.scene();
  refreshStranded(forbidden);
  std::vector<std::vector<std::pair<VertexId, double>>> reverse(g.vertexCount());
  for (HyperarcId a : g.hyperarcs()) {
    if (forbidden.contains(a) || strandsRobot(a)) continue;
    const auto [from, to] = objectMove(a);
    if (from.valid() && to.valid()) reverse[to.value()].push_back({from, graph_->cost(a)});
  }
  // Backward Dijkstra over the object states from those `finished` says are done.
  auto costs = [&](auto finished) {
    std::vector<double> out(g.vertexCount(), 0.0);
    using Item = std::pair<double, VertexId>;
    std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
    for (VertexId v : g.vertices()) {
      const MotionVertex& mv = g.property(v);
      if (!isObjectState(mv)) continue;
      out[v.value()] = finished(mv) ? 0.0 : kInf;
      if (out[v.value()] == 0.0) open.push({0.0, v});
    }
    while (!open.empty()) {
      const auto [d, v] = open.top();
      open.pop();
      if (d > out[v.value()]) continue;
      for (const auto& [u, c] : reverse[v.value()])
        if (d + c < out[u.value()]) {
          out[u.value()] = d + c;
          open.push({d + c, u});
        }
    }
    return out;
  };
  to_goal_ = costs([&](const MotionVertex& mv) {
    const int goal = space.goalLocation(mv.object);
    return mv.kind == Kind::kObject && (goal < 0 || mv.placement == goal);
  });
  // Objects a pending inspection needs away from their start (lab lids): anywhere else will do.
  to_away_ = costs([&](const MotionVertex& mv) {
    return mv.kind == Kind::kObject && mv.placement != space.startLocation(mv.object);
  });
  pending_of_.assign(scene.objects.size(), {});
  for (VertexId v : g.vertices()) {
    const MotionVertex& mv = g.property(v);
    if (mv.kind != Kind::kTaskPending) continue;
    const int lid = scene.tasks[mv.task].requires_removed_object;
    if (lid >= 0) pending_of_[lid].push_back(v);
  }
}

void CombinedQuery::refreshStranded(const std::unordered_set<HyperarcId>& forbidden) {
  const MotionGraph& g = graph_->graph();
  const TaskSpace& space = graph_->space();
  const Scene& scene = space.scene();
  std::vector<char> needed_away(scene.objects.size(), 0);
  for (const auto& task : scene.tasks)
    if (task.requires_removed_object >= 0) needed_away[task.requires_removed_object] = 1;
  // A pick of an object at its goal (one no inspection needs away) is not a way home: the goal needs
  // the object back there, so such a pick right after the place that left the robot there only undoes
  // it, and H_M never needs a goal cleared (resting objects block no transition of H_M).
  auto undoesGoal = [&](HyperarcId a) {
    if (g.property(a).type != Type::kPick) return false;
    for (VertexId t : g.tail(a)) {
      const MotionVertex& tv = g.property(t);
      if (tv.kind == Kind::kObject && !needed_away[tv.object] && tv.placement == space.goalLocation(tv.object)) return true;
    }
    return false;
  };
  // A move back from a handover is not a way home either: a robot goes to wait there only for the
  // handover, so where every handover from there strands it, going there is the mistake (and the
  // greedy pass, which never moves back, would be stuck there).
  auto movesBack = [&](HyperarcId a) {
    const MotionArc& arc = g.property(a);
    return arc.type == Type::kMove && graph_->move(arc.index).back;
  };
  // Reverse robot steps: for each hyperarc, each robot's vertex before it from the one after it.
  std::vector<std::vector<VertexId>> before(g.vertexCount());
  for (HyperarcId a : g.hyperarcs()) {
    if (forbidden.contains(a) || undoesGoal(a) || movesBack(a)) continue;
    for (VertexId h : g.head(a)) {
      const MotionVertex& hv = g.property(h);
      if (!isRobotState(hv)) continue;
      for (VertexId t : g.tail(a)) {
        const MotionVertex& tv = g.property(t);
        if (isRobotState(tv) && tv.robot == hv.robot && t != h) before[h.value()].push_back(t);
      }
    }
  }
  std::vector<char> reaches_home(g.vertexCount(), 0);
  std::vector<VertexId> open;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    const VertexId home = graph_->homeVertex(r);
    reaches_home[home.value()] = 1;
    open.push_back(home);
  }
  while (!open.empty()) {
    const VertexId v = open.back();
    open.pop_back();
    for (VertexId u : before[v.value()])
      if (!reaches_home[u.value()]) {
        reaches_home[u.value()] = 1;
        open.push_back(u);
      }
  }
  strands_.assign(g.hyperarcCount(), 0);
  if (!stranding_prune_) return;
  for (HyperarcId a : g.hyperarcs())
    for (VertexId h : g.head(a))
      if (isRobotState(g.property(h)) && !reaches_home[h.value()]) strands_[a.value()] = 1;
}

double CombinedQuery::costToGo(const HyperpathState& state, VertexId v) const {
  const MotionVertex& mv = graph_->graph().property(v);
  if (!isObjectState(mv)) return 0.0;
  for (VertexId pending : pending_of_[mv.object])
    if (state.inFrontier(pending)) return to_away_[v.value()];
  return to_goal_[v.value()];
}

int CombinedQuery::firstUnfinished(const HyperpathState& state) const {
  const MotionGraph& g = graph_->graph();
  int first = -1;
  for (ExtendedVertexId instance : state.frontier()) {
    const VertexId v = state.vertexOf(instance);
    const MotionVertex& mv = g.property(v);
    if (isObjectState(mv) && (first < 0 || mv.object < first) && costToGo(state, v) > 0.0) first = mv.object;
  }
  return first;
}

bool CombinedQuery::placementFree(const HyperpathState& state, HyperarcId a) const {
  const MotionGraph& g = graph_->graph();
  if (g.property(a).type != Type::kPlace) return true;
  for (VertexId v : g.head(a)) {
    const int spot = graph_->spotOf(v);
    if (spot < 0) continue;
    for (VertexId other : graph_->spotVertices(spot))
      if (other != v && state.inFrontier(other)) return false;
  }
  return true;
}

double CombinedQuery::regret(const HyperpathState& state, HyperarcId a) const {
  const auto [from, to] = objectMove(a);
  if (!from.valid() || !to.valid()) return graph_->cost(a);
  return graph_->cost(a) + costToGo(state, to) - costToGo(state, from);
}

double CombinedQuery::priority(const HyperpathState& state, HyperarcId a, Summary& summary, Pass which) const {
  const MotionGraph& g = graph_->graph();
  const MotionArc& arc = g.property(a);
  if (strandsRobot(a)) return kInf;
  if (!summary.valid || summary.node != state.node()) {
    summary.valid = true;
    summary.node = state.node();
    summary.robot_at.assign(graph_->space().scene().robots.size(), VertexId());
    for (ExtendedVertexId instance : state.frontier()) {
      const VertexId v = state.vertexOf(instance);
      const MotionVertex& mv = g.property(v);
      if (mv.kind == Kind::kRobot || mv.kind == Kind::kHolding) summary.robot_at[mv.robot] = v;
    }
    summary.focus = which == Pass::kOneObjectAtATime ? firstUnfinished(state) : -1;
  }
  // The one-object pass moves only the first object not yet finished.
  if (which == Pass::kOneObjectAtATime) {
    const VertexId moved = objectMove(a).first;
    if (moved.valid() && g.property(moved).object != summary.focus) return kInf;
  }
  if (arc.type == Type::kInspect) return 0.0;
  if (arc.type != Type::kMove) {
    const auto [from, to] = objectMove(a);
    const double r = regret(state, a);
    if (!std::isfinite(r)) return kInf;
    if (costToGo(state, from) == 0.0 && costToGo(state, to) > 0.0) return kUndo + r;
    if (r > kOnRoute) return kDetour + r;
    return (arc.type == Type::kPick ? kPickPenalty : 0.0) + r;
  }
  return movePriority(state, a, summary, which);
}

double CombinedQuery::movePriority(const HyperpathState& state, HyperarcId a, const Summary& summary,
                                   Pass which) const {
  const bool complete = which == Pass::kComplete;
  const MotionGraph& g = graph_->graph();
  const MotionArc& arc = g.property(a);
  auto emptyHanded = [&](int robot) {
    const VertexId v = summary.robot_at[robot];
    return v.valid() && g.property(v).kind == Kind::kRobot;
  };
  const VertexId from = g.tail(a).front();
  const VertexId to = g.head(a).front();
  const double cost = graph_->cost(a);
  const MotionVertex& mv = g.property(from);
  const TransitionCatalog& catalog = graph_->catalog();
  // Back from a handover its partner did not come to: a way out of a tangle, not a step towards the
  // goal (in the greedy pass such detours made it wander past its budget on sorting 4/64).
  if (graph_->move(arc.index).back) {
    if (which == Pass::kGreedy) return kInf;
    return (mv.kind == Kind::kRobot ? kHome : kIdleMove) + cost;
  }
  if (mv.kind == Kind::kHolding) {
    const double r = cost + costToGo(state, to) - costToGo(state, from);
    if (!std::isfinite(r)) return kInf;
    double level = kInf;
    for (HyperarcId t : graph_->transitionsFrom(to)) {
      const MotionArc& ta = g.property(t);
      if (ta.type == Type::kPlace && placementFree(state, t)) level = std::min(level, kHoldMove);
      if (ta.type == Type::kHandover) {
        const HandoverSample& h = catalog.handovers[ta.index];
        if (h.giver != mv.robot || !emptyHanded(h.receiver)) continue;
        bool waiting = false;
        for (VertexId v : g.tail(t)) waiting = waiting || (v != to && state.inFrontier(v));
        level = std::min(level, kHoldMove - (waiting ? kPartnerWaiting : 0.0));
      }
    }
    if (!std::isfinite(level)) return complete ? kIdleMove + cost : kInf;
    return (r > kOnRoute ? kDetour : level) + r;
  }
  if (to == graph_->homeVertex(mv.robot)) return kHome + cost;
  double best = kInf;
  for (HyperarcId t : graph_->transitionsFrom(to)) {
    const MotionArc& ta = g.property(t);
    double value = kInf;
    if (ta.type == Type::kPick) {
      const auto [object_at, held] = objectMove(t);
      if (!state.inFrontier(object_at)) continue;
      // The one-object pass picks only its object: going to wait by another is a wasted move.
      if (which == Pass::kOneObjectAtATime && g.property(object_at).object != summary.focus) continue;
      const double r = regret(state, t);
      const bool undo = costToGo(state, object_at) == 0.0 && costToGo(state, held) > 0.0;
      value = (undo ? kUndoMove : kPickMove) + r;
    } else if (ta.type == Type::kHandover) {
      const HandoverSample& h = catalog.handovers[ta.index];
      if (h.receiver != mv.robot) continue;
      const VertexId giver_at = summary.robot_at[h.giver];
      VertexId giver_vertex;
      for (VertexId v : g.tail(t))
        if (v != to) giver_vertex = v;
      if (!giver_at.valid()) continue;
      const MotionVertex& gv = g.property(giver_at);
      const MotionVertex& need = g.property(giver_vertex);
      if (gv.kind != Kind::kHolding || gv.object != need.object || gv.grasp != need.grasp) continue;
      value = kReceiveMove - (giver_at == giver_vertex ? kPartnerWaiting : 0.0) + regret(state, t);
    } else if (ta.type == Type::kInspect) {
      bool ready = true;
      for (VertexId v : g.tail(t)) ready = ready && (v == to || state.inFrontier(v));
      if (ready) value = kInspectMove;
    }
    best = std::min(best, value);
  }
  if (!std::isfinite(best) && complete) best = kIdleMove;
  return best + cost;
}

HyperpathResult CombinedQuery::run(const std::vector<MotionConstraint>& constraints, const CombinedQueryParams& params,
                                   const Deadline& deadline, std::function<void(const ExtendedVertex&)> on_vertex,
                                   std::function<void(const ExtendedHyperarc&)> on_hyperarc) {
  stranding_prune_ = params.stranding_prune;
  refresh(alwaysForbidden(constraints));
  const MotionGraph& g = graph_->graph();
  HyperpathSearchParams search;
  search.algorithm = HyperpathAlgorithm::kGreedy;
  search.allowed = [this, &constraints, &g](const HyperpathState& state, HyperarcId a) {
    for (const MotionConstraint& c : constraints)
      if (violates(g, state, a, c)) return false;
    return placementFree(state, a);
  };
  // Only for pruning: a state the goal cannot be reached from (either way of counting).
  search.costToGo = [this](VertexId v) { return std::min(to_goal_[v.value()], to_away_[v.value()]); };
  search.arcCost = [this](HyperarcId a) { return graph_->cost(a); };
  search.deadline = deadline;
  search.onExtendedVertex = std::move(on_vertex);
  search.onExtendedHyperarc = std::move(on_hyperarc);
  search.maxPendingSuccessors = params.max_pending_successors;
  auto pass = [&](Pass which) {
    auto summary = std::make_shared<Summary>();
    search.priority = [this, summary, which](const HyperpathState& state, HyperarcId a) {
      return priority(state, a, *summary, which);
    };
    const std::size_t frontier = std::max<std::size_t>(1, g.head(graph_->source()).size());
    search.maxExpansions = std::min(which == Pass::kGreedy     ? params.max_expansions
                                    : which == Pass::kComplete ? params.complete_max_expansions
                                                               : params.one_object_max_expansions,
                                    params.max_frontier_entries / frontier);
    last_pass_ = which;
    return findHyperpath(g, {graph_->source(), graph_->sink()}, search);
  };
  // Without pruned moves the first pass is the complete one: nothing is left for another.
  HyperpathResult result = pass(params.prune_moves ? Pass::kGreedy : Pass::kComplete);
  std::size_t expansions = result.stats.expansions;
  auto done = [&] { return result.found() || result.status == HyperpathStatus::kDeadline; };
  if (done() || !params.prune_moves) return result;
  if (params.one_object_pass) {
    result = pass(Pass::kOneObjectAtATime);
    expansions += result.stats.expansions;
    result.stats.expansions = expansions;
    if (done()) return result;
  }
  if (!params.complete_pass) return result;
  result = pass(Pass::kComplete);
  result.stats.expansions += expansions;
  return result;
}

}  // namespace dash
