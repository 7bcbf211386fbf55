#include "engine/motion/context_lazy_prm.h"

#include "engine/motion/kd_neighbors.h"

#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <boost/graph/lookup_edge.hpp>

#include <algorithm>
#include <limits>
#include <queue>
#include <tuple>

namespace ob = ompl::base;

namespace dash {

ContextLazyPRM::ContextLazyPRM(const ob::SpaceInformationPtr& static_si) : LazyPRM(static_si, false) {
  // og::LazyPRM takes its edge-cost objective (path length) from the problem definition in setup().
  setProblemDefinition(std::make_shared<ob::ProblemDefinition>(si_));
  // The k-d tree in place of the GNAT og::LazyPRM would make in setMaxNearestNeighbors (kd_neighbors.h),
  // with the distance og::LazyPRM's connection strategy filters by.
  nn_ = std::make_shared<KdNeighbors<Vertex>>(
      si_->getStateDimension(),
      [this](const Vertex& v) { return stateProperty_[v]->as<ob::RealVectorStateSpace::StateType>()->values; });
  nn_->setDistanceFunction([this](const Vertex a, const Vertex b) { return distanceFunction(a, b); });
}

void ContextLazyPRM::forgetContext() {
  if (generation_ < kLastGeneration) {
    ++generation_;
    return;
  }
  // Generations ran out (after half a billion contexts): clear every tag and start again.
  for (const auto v : boost::make_iterator_range(boost::vertices(g_))) vertexValidityProperty_[v] &= VALIDITY_TRUE;
  for (const auto& e : boost::make_iterator_range(boost::edges(g_))) edgeValidityProperty_[e] &= VALIDITY_TRUE;
  generation_ = 1;
}

int ContextLazyPRM::contextVerdict(unsigned int flags) const {
  if ((flags >> kGenerationShift) != generation_) return -1;
  return (flags & kContextValid) != 0 ? 1 : 0;
}

void ContextLazyPRM::setContextVerdict(unsigned int& flags, bool valid) const {
  flags = (flags & VALIDITY_TRUE) | (valid ? kContextValid : kContextInvalid) | (generation_ << kGenerationShift);
}

std::size_t ContextLazyPRM::sampleBatch(std::size_t vertices) { return std::max<std::size_t>(1, vertices / 64); }

ContextLazyPRM::Vertex ContextLazyPRM::addNumberedMilestone(ob::State* state) {
  const Vertex v = addMilestone(state);
  indexProperty_[v] = next_id_++;  // ids are never reused: the search workspace and tie-breaks use them
  return v;
}

ContextLazyPRM::Vertex ContextLazyPRM::endMilestone(const ob::State* state) {
  const auto* values = state->as<ob::RealVectorStateSpace::StateType>()->values;
  std::vector<double> key(values, values + si_->getStateDimension());
  if (auto it = ends_.find(key); it != ends_.end()) return it->second;
  const Vertex v = addNumberedMilestone(si_->cloneState(state));
  ends_.emplace(std::move(key), v);
  return v;
}

void ContextLazyPRM::addPath(const std::vector<const ob::State*>& states) {
  // No state twice (RRT-Connect's trees may meet at one): equal states tie in every neighbour query.
  // The last state is the query's goal and stays.
  std::vector<const ob::State*> kept;
  for (std::size_t i = 0; i < states.size(); ++i) {
    if (!kept.empty() && si_->distance(kept.back(), states[i]) < 1e-9) {
      if (i + 1 == states.size() && kept.size() > 1) kept.back() = states[i];
      continue;
    }
    kept.push_back(states[i]);
  }
  Vertex before = nullptr;
  for (std::size_t i = 0; i < kept.size(); ++i) {
    // The ends are the query's, already in the roadmap (deduplicated as query ends).
    const bool end = i == 0 || i + 1 == kept.size();
    const Vertex v = end ? endMilestone(kept[i]) : addNumberedMilestone(si_->cloneState(kept[i]));
    if (before != nullptr && before != v && !boost::edge(before, v, g_).second) {
      const ob::Cost weight = opt_->motionCost(stateProperty_[before], stateProperty_[v]);
      const Graph::edge_property_type properties(weight);
      const Edge e = boost::add_edge(before, v, properties, g_).first;
      edgeValidityProperty_[e] = VALIDITY_UNKNOWN;
      uniteComponents(before, v);
    }
    before = v;
  }
}

void ContextLazyPRM::removeMilestone(Vertex v) {
  nn_->remove(v);
  si_->freeState(stateProperty_[v]);
  boost::clear_vertex(v, g_);
  boost::remove_vertex(v, g_);
}

std::vector<ContextLazyPRM::Vertex> ContextLazyPRM::shortestPath(Vertex start, Vertex goal) {
  if (search_.size() < next_id_) search_.resize(next_id_ + next_id_ / 2);
  const std::uint32_t stamp = ++search_stamp_;
  const ob::State* target = stateProperty_[goal];
  auto heuristic = [&](Vertex v, SearchNode& node) {
    if (node.h_stamp != query_stamp_) {
      node.h = si_->distance(stateProperty_[v], target);
      node.h_stamp = query_stamp_;
    }
    return node.h;
  };
  using Item = std::tuple<double, std::size_t, double, Vertex>;  // f, id (a deterministic tie-break), g, vertex
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  SearchNode& first = search_[id(start)];
  first.g = 0.0;
  first.pred = nullptr;
  first.stamp = stamp;
  open.emplace(heuristic(start, first), id(start), 0.0, start);
  bool reached = false;
  while (!open.empty()) {
    const auto [f, vid, g_v, v] = open.top();
    open.pop();
    if (v == goal) {
      reached = true;
      break;
    }
    if (g_v > search_[vid].g) continue;  // a stale entry
    for (const auto& e : boost::make_iterator_range(boost::out_edges(v, g_))) {
      const Vertex w = boost::target(e, g_);
      if (contextVerdict(edgeValidityProperty_[e]) == 0 || contextVerdict(vertexValidityProperty_[w]) == 0) continue;
      const double g_w = g_v + weightProperty_[e].value();
      SearchNode& node = search_[id(w)];
      if (node.stamp != stamp || g_w < node.g) {
        node.g = g_w;
        node.pred = v;
        node.stamp = stamp;
        open.emplace(g_w + heuristic(w, node), id(w), g_w, w);
      }
    }
  }
  if (!reached) return {};
  std::vector<Vertex> path;
  for (Vertex v = goal; v != nullptr; v = search_[id(v)].pred) path.push_back(v);
  std::reverse(path.begin(), path.end());
  return path;
}

bool ContextLazyPRM::validatePath(const std::vector<Vertex>& path, const StateCheck& context_state,
                                  const MotionCheck& context_motion) {
  // Every vertex first (og::LazyPRM's order: a vertex can cut off more than an edge).
  std::vector<Vertex> statically_invalid;
  bool all_valid = true;
  for (Vertex v : path) {
    unsigned int& flags = vertexValidityProperty_[v];
    if ((flags & VALIDITY_TRUE) == 0) {
      if (!si_->isValid(stateProperty_[v])) {
        statically_invalid.push_back(v);
        continue;
      }
      flags |= VALIDITY_TRUE;
    }
    if (contextVerdict(flags) < 0) setContextVerdict(flags, context_state(stateProperty_[v]));
    all_valid = all_valid && contextVerdict(flags) == 1;
  }
  for (Vertex v : statically_invalid) removeMilestone(v);
  if (!all_valid || !statically_invalid.empty()) return false;
  // Then the edges, up to the first invalid one.
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Vertex a = path[i - 1], b = path[i];
    const Edge e = boost::lookup_edge(a, b, g_).first;
    unsigned int& flags = edgeValidityProperty_[e];
    if ((flags & VALIDITY_TRUE) == 0) {
      if (!si_->checkMotion(stateProperty_[a], stateProperty_[b])) {
        boost::remove_edge(e, g_);
        return false;
      }
      flags |= VALIDITY_TRUE;
    }
    if (contextVerdict(flags) < 0) setContextVerdict(flags, context_motion(stateProperty_[a], stateProperty_[b]));
    if (contextVerdict(flags) == 0) return false;
  }
  return true;
}

std::optional<std::vector<const ob::State*>> ContextLazyPRM::solveInContext(const ob::State* start,
                                                                            const ob::State* goal,
                                                                            std::size_t samples,
                                                                            const StopCondition& stop,
                                                                            const StateCheck& context_state,
                                                                            const MotionCheck& context_motion) {
  // The ends are valid in the context, hence statically: marked so, never removed.
  const Vertex s = endMilestone(start);
  const Vertex t = endMilestone(goal);
  for (Vertex v : {s, t}) {
    vertexValidityProperty_[v] |= VALIDITY_TRUE;
    setContextVerdict(vertexValidityProperty_[v], true);
  }
  ++query_stamp_;  // a new goal: the heuristic values of the last query are void
  ob::State* work = si_->allocState();
  std::size_t drawn = 0;
  std::optional<std::vector<const ob::State*>> found;
  while (!stop()) {
    const std::vector<Vertex> path = shortestPath(s, t);
    if (!path.empty()) {
      if (validatePath(path, context_state, context_motion)) {
        found.emplace();
        for (Vertex v : path) found->push_back(stateProperty_[v]);
        break;
      }
      continue;  // something on the path was invalid and is now out of the search: search again
    }
    if (drawn >= samples) break;
    const std::size_t batch = std::min(sampleBatch(boost::num_vertices(g_)), samples - drawn);
    for (std::size_t i = 0; i < batch; ++i) {
      sampler_->sampleUniform(work);
      addNumberedMilestone(si_->cloneState(work));
    }
    drawn += batch;
  }
  si_->freeState(work);
  return found;
}

}  // namespace dash
