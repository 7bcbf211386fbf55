#pragma once
// Small hand-built hypergraphs for the hyperpath search tests, with named vertices and hyperarcs.
#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

#include "engine/hypergraph/hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"

namespace dash::testing {

struct NamedGraph {
  Hypergraph<std::string, std::string> graph;
  std::unordered_map<std::string, HyperarcId> arcs;

  VertexId v(const std::string& name) { return graph.addVertex(name).id; }
  HyperarcId arc(const std::string& name, const std::vector<std::string>& tail,
                 const std::vector<std::string>& head) {
    std::vector<VertexId> t, h;
    for (const auto& n : tail) t.push_back(v(n));
    for (const auto& n : head) h.push_back(v(n));
    const HyperarcId id = graph.addHyperarc(t, h, name).id;
    arcs[name] = id;
    return id;
  }
  HyperarcId operator[](const std::string& name) const { return arcs.at(name); }
  VertexId vertex(const std::string& name) const { return *graph.find(name); }
  HyperpathQuery query() const { return {arcs.at("source"), arcs.at("sink")}; }

  std::vector<std::string> names(const HyperpathResult& result) const {
    std::vector<std::string> out;
    for (const auto& step : result.steps) out.push_back(graph.property(step.hyperarc));
    return out;
  }
  std::size_t stepIndex(const HyperpathResult& result, const std::string& name) const {
    for (std::size_t s = 0; s < result.steps.size(); ++s)
      if (graph.property(result.steps[s].hyperarc) == name) return s;
    ADD_FAILURE() << "no step " << name;
    return 0;
  }
};

/// Two robots, one object, one handover: R1 reaches only the start, R2 only the goal.
/// With `reachableGoal` false nothing can place the object at its goal (an infeasible problem that
/// still has cycles: pick then place back, hand over and back).
inline NamedGraph handoverGraph(bool reachableGoal = true) {
  NamedGraph g;
  g.arc("source", {"src"}, {"R1", "R2", "O_s"});
  g.arc("pick1", {"R1", "O_s"}, {"R1+O"});
  g.arc("place1", {"R1+O"}, {"R1", "O_s"});
  g.arc("handover12", {"R1+O", "R2"}, {"R1", "R2+O"});
  g.arc("handover21", {"R2+O", "R1"}, {"R2", "R1+O"});
  if (reachableGoal) {
    g.arc("place2", {"R2+O"}, {"R2", "O_g"});
    g.arc("pick2", {"R2", "O_g"}, {"R2+O"});
  }
  g.arc("sink", {"O_g"}, {"sink"});
  return g;
}

/// Checks a found hyperpath by replaying it: each step consumes live instances of its tail vertices
/// (so none is consumed twice), produces fresh instances of its head, and dependsOn names exactly
/// the producers of what it consumes.
inline void expectValidHyperpath(const NamedGraph& g, const HyperpathQuery& query, const HyperpathResult& result) {
  ASSERT_TRUE(result.found());
  ASSERT_GE(result.steps.size(), 2u);
  EXPECT_EQ(result.steps.front().hyperarc, query.source);
  EXPECT_TRUE(result.steps.front().consumed.empty());
  EXPECT_EQ(result.steps.back().hyperarc, query.sink);
  std::map<ExtendedVertexId, std::pair<VertexId, std::size_t>> live;  // instance -> vertex, producer step
  std::set<ExtendedVertexId> seen;
  for (std::size_t s = 0; s < result.steps.size(); ++s) {
    const HyperpathStep& step = result.steps[s];
    const auto tail = g.graph.tail(step.hyperarc);
    const auto head = g.graph.head(step.hyperarc);
    std::set<std::size_t> producers;
    if (s > 0) {
      ASSERT_EQ(step.consumed.size(), tail.size());
      for (std::size_t i = 0; i < tail.size(); ++i) {
        const auto it = live.find(step.consumed[i]);
        ASSERT_NE(it, live.end()) << "step " << s << " consumes an instance that is not live";
        EXPECT_EQ(it->second.first, tail[i]);
        producers.insert(it->second.second);
        live.erase(it);
      }
    }
    EXPECT_EQ(std::vector<std::size_t>(producers.begin(), producers.end()), step.dependsOn);
    ASSERT_EQ(step.produced.size(), head.size());
    for (std::size_t j = 0; j < head.size(); ++j) {
      EXPECT_TRUE(seen.insert(step.produced[j]).second) << "instance produced twice";
      live[step.produced[j]] = {head[j], s};
    }
  }
}

}  // namespace dash::testing
