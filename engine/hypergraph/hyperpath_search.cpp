#include "engine/hypergraph/hyperpath_search.h"

#include <algorithm>
#include <cmath>
#include <queue>

#include "engine/core/stopwatch.h"
#include "engine/hypergraph/search_workspace.h"

namespace dash {
namespace {

using detail::SearchWorkspace;
using detail::StateTable;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

struct Outcome {
  HyperpathStatus status = HyperpathStatus::kExhausted;
  ExtendedHyperarcId goal;  // the node that applied the sink, when found
};

bool allows(const HyperpathSearchParams& params, const HyperpathState& state, HyperarcId arc) {
  return !params.allowed || params.allowed(state, arc);
}

HyperpathStatus exhaustedOrCut(const HyperpathStats& stats) {
  // States cut off by maxDepth were never explored, so running out proves nothing.
  return stats.depthCutoffs > 0 ? HyperpathStatus::kBudget : HyperpathStatus::kExhausted;
}

bool isSourceOrSink(const SearchWorkspace& ws, HyperarcId a) { return a == ws.sink() || a == ws.source(); }

// Depth-first over histories, successors by increasing priority, backtracking on dead ends: the
// greedy hyperpath query of DaSH / Lazy-DaSH. Departure from the authors' query: visited states are
// memoised on the frontier multiset (plus the history-relevant vertices), so a state reached through
// another order of independent steps is not searched again; this is what bounds the search.
Outcome runGreedy(SearchWorkspace& ws, const HyperpathSearchParams& params, HyperpathStats& stats) {
  struct Candidate {
    bool postponed;  // undoes finished work: tried after every other successor
    double priority;
    HyperarcId arc;
  };
  // A min-heap per state: usually only the first successor or two are ever tried.
  auto later = [](const Candidate& x, const Candidate& y) {
    if (x.postponed != y.postponed) return x.postponed;
    return x.priority != y.priority ? x.priority > y.priority : x.arc > y.arc;
  };
  struct Frame {
    std::size_t begin;  // this state's untried candidates: candidates[begin, end), a heap
    std::size_t end;
  };
  std::vector<Candidate> candidates;
  std::vector<Frame> stack;
  const HyperpathState view = ws.view();  // reads the workspace's current state live
  bool entered = true;                    // the current state has not been expanded yet
  while (true) {
    if (params.deadline.expired()) return {HyperpathStatus::kDeadline, {}};
    if (entered) {
      entered = false;
      if (ws.sinkApplicable()) {
        if (allows(params, view, ws.sink())) return {HyperpathStatus::kFound, ws.addChild(ws.sink(), StateTable::kNone)};
        ++stats.pruned;
      }
      if (stats.expansions >= params.maxExpansions) return {HyperpathStatus::kBudget, {}};
      ++stats.expansions;
      Frame frame{candidates.size(), candidates.size()};
      if (ws.node(ws.current()).depth >= params.maxDepth) {
        ++stats.depthCutoffs;
      } else {
        for (HyperarcId a : ws.applicable()) {
          if (isSourceOrSink(ws, a)) continue;
          if (!allows(params, view, a)) {
            ++stats.pruned;
            continue;
          }
          const double priority = params.priority ? params.priority(view, a) : ws.defaultPriority(a);
          if (!(priority < kInfinity)) {  // a head vertex from which the goal cannot be reached
            ++stats.pruned;
            continue;
          }
          // The authors' query drops a step that takes finished work (costToGo 0, e.g. an object at
          // its goal) back to unfinished; without that the greedy descent wanders through such
          // moves. Departure: it is only postponed, so the search stays complete (a non-monotone
          // problem may need to move a finished object out of the way).
          const bool postponed = !params.priority && ws.undoesFinishedWork(a);
          candidates.push_back({postponed, priority, a});
        }
        if (candidates.size() > params.maxPendingSuccessors) return {HyperpathStatus::kBudget, {}};
        std::make_heap(candidates.begin() + static_cast<std::ptrdiff_t>(frame.begin), candidates.end(), later);
      }
      frame.end = candidates.size();
      stack.push_back(frame);
    }
    Frame& top = stack.back();  // the last frame: its candidates end the vector
    if (top.begin < top.end) {
      std::pop_heap(candidates.begin() + static_cast<std::ptrdiff_t>(top.begin), candidates.end(), later);
      const HyperarcId arc = candidates.back().arc;
      candidates.pop_back();
      --top.end;
      const detail::SuccessorKey key = ws.successorKey(arc);
      const StateTable::Lookup lookup = ws.states().insert(key.hash, key.key);
      if (!lookup.inserted) {
        ++stats.duplicates;
        continue;
      }
      ws.enter(ws.addChild(arc, lookup.index));
      entered = true;
      continue;
    }
    stack.pop_back();
    if (stack.empty()) return {exhaustedOrCut(stats), {}};
    ws.undo();
    ++stats.backtracks;
  }
}

// Best-first over states, f = g + w * h, g the sum of arc costs, h from costToGo over the frontier
// (max or sum). The goal test happens when the sink's node is popped, so with an admissible h the
// first hyperpath found is a cheapest one (Dijkstra-like without costToGo, A*-like with it).
Outcome runBestFirst(SearchWorkspace& ws, const HyperpathSearchParams& params, HyperpathStats& stats) {
  struct Open {
    double f;
    double g;
    std::uint64_t seq;
    ExtendedHyperarcId node;
  };
  // Lowest f first; among equal f the deeper (larger g), then the older.
  auto worse = [](const Open& x, const Open& y) {
    if (x.f != y.f) return x.f > y.f;
    if (x.g != y.g) return x.g < y.g;
    return x.seq > y.seq;
  };
  std::priority_queue<Open, std::vector<Open>, decltype(worse)> open(worse);
  std::uint64_t seq = 0;
  const HyperpathState view = ws.view();

  const double rootH = ws.heuristic(ws.successorKey(HyperarcId()).key);
  if (!(rootH < kInfinity)) return {HyperpathStatus::kExhausted, {}};
  ws.states().bestCost(ws.node(ws.current()).state) = 0.0;
  open.push({params.heuristicWeight * rootH, 0.0, seq++, ws.current()});

  while (!open.empty()) {
    if (params.deadline.expired()) return {HyperpathStatus::kDeadline, {}};
    const Open top = open.top();
    open.pop();
    const detail::SearchNode node = ws.node(top.node);  // a copy: nodes are added below
    if (node.reachesSink) return {HyperpathStatus::kFound, top.node};
    if (node.cost > ws.states().bestCost(node.state)) continue;  // superseded by a cheaper history
    if (stats.expansions >= params.maxExpansions) return {HyperpathStatus::kBudget, {}};
    ++stats.expansions;
    ws.moveTo(top.node);
    if (node.depth >= params.maxDepth) {
      ++stats.depthCutoffs;
      continue;
    }
    if (ws.sinkApplicable()) {
      if (allows(params, view, ws.sink())) {
        const ExtendedHyperarcId goal = ws.addChild(ws.sink(), StateTable::kNone);
        const double g = ws.node(goal).cost;
        open.push({g, g, seq++, goal});
      } else {
        ++stats.pruned;
      }
    }
    // Successors are judged without being applied, so the applicable list does not change here.
    for (HyperarcId a : ws.applicable()) {
      if (isSourceOrSink(ws, a)) continue;
      if (!allows(params, view, a)) {
        ++stats.pruned;
        continue;
      }
      const double g = node.cost + ws.arcCost(a);
      const detail::SuccessorKey key = ws.successorKey(a);
      const double h = ws.heuristic(key.key);
      if (!(h < kInfinity)) {  // some frontier vertex cannot reach the goal
        ++stats.pruned;
        continue;
      }
      std::uint32_t state = ws.states().find(key.hash, key.key);
      if (state != StateTable::kNone && ws.states().bestCost(state) <= g) {
        ++stats.duplicates;
        continue;
      }
      if (state == StateTable::kNone) state = ws.states().insert(key.hash, key.key).index;
      ws.states().bestCost(state) = g;
      open.push({g + params.heuristicWeight * h, g, seq++, ws.addChild(a, state)});
    }
  }
  return {exhaustedOrCut(stats), {}};
}

}  // namespace

std::string_view toString(HyperpathStatus status) {
  switch (status) {
    case HyperpathStatus::kFound: return "found";
    case HyperpathStatus::kExhausted: return "exhausted";
    case HyperpathStatus::kDeadline: return "deadline";
    case HyperpathStatus::kBudget: return "budget";
  }
  return "unknown";
}

HyperpathResult findHyperpath(const HypergraphTopology& graph, const HyperpathQuery& query,
                              const HyperpathSearchParams& params) {
  const Stopwatch watch;
  HyperpathResult result;
  SearchWorkspace ws(graph, query, params, result.stats);
  const Outcome outcome = params.algorithm == HyperpathAlgorithm::kGreedy ? runGreedy(ws, params, result.stats)
                                                                          : runBestFirst(ws, params, result.stats);
  result.status = outcome.status;
  result.stats.statesVisited = ws.states().size();
  if (outcome.status == HyperpathStatus::kFound) {
    result.steps = ws.extractSteps(outcome.goal);
    result.cost = ws.node(outcome.goal).cost;
  }
  result.stats.seconds = watch.seconds();
  return result;
}

HyperarcFilter allOf(HyperarcFilter first, HyperarcFilter second) {
  if (!first) return second;
  if (!second) return first;
  return [first = std::move(first), second = std::move(second)](const HyperpathState& state, HyperarcId arc) {
    return first(state, arc) && second(state, arc);
  };
}

}  // namespace dash
