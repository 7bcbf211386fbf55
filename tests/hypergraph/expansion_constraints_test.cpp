#include "engine/hypergraph/expansion_constraints.h"

#include <gtest/gtest.h>

#include "tests/hypergraph/test_graphs.h"

namespace dash {
namespace {

using testing::expectValidHyperpath;
using testing::NamedGraph;
using Names = std::vector<std::string>;

class Constraints : public ::testing::TestWithParam<HyperpathAlgorithm> {};

INSTANTIATE_TEST_SUITE_P(Hyperpath, Constraints,
                         ::testing::Values(HyperpathAlgorithm::kGreedy, HyperpathAlgorithm::kBestFirst),
                         [](const auto& info) {
                           return info.param == HyperpathAlgorithm::kGreedy ? "Greedy" : "BestFirst";
                         });

// Two independent threads: X moves X -> X2 -> X3, Y moves Y -> Y2. Left alone, both searches move
// Y last (its move is the expensive one).
NamedGraph twoThreads() {
  NamedGraph g;
  g.arc("source", {"src"}, {"X", "Y"});
  g.arc("moveX", {"X"}, {"X2"});
  g.arc("moveX2", {"X2"}, {"X3"});
  g.arc("moveY", {"Y"}, {"Y2"});
  g.arc("sink", {"X3", "Y2"}, {"sink"});
  return g;
}

HyperpathSearchParams paramsFor(const NamedGraph& g, HyperpathAlgorithm algorithm) {
  HyperpathSearchParams p{.algorithm = algorithm};
  p.arcCost = [&g](HyperarcId a) { return a == g["moveY"] ? 3.0 : 1.0; };
  return p;
}

TEST_P(Constraints, UnconstrainedMovesYLast) {
  const NamedGraph g = twoThreads();
  const HyperpathResult result = findHyperpath(g.graph, g.query(), paramsFor(g, GetParam()));
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "moveX", "moveX2", "moveY", "sink"}));
}

TEST_P(Constraints, FrontierConstraintWaitsUntilPreLeavesTheFrontier) {
  const NamedGraph g = twoThreads();
  ExpansionConstraints c;
  EXPECT_TRUE(c.addFrontier(g.vertex("X"), g.vertex("Y2")));   // Y2 only once X has moved on
  EXPECT_TRUE(c.addFrontier(g.vertex("X3"), g.vertex("Y2")));  // ...and before X reaches X3
  EXPECT_FALSE(c.addFrontier(g.vertex("X"), g.vertex("Y2")));
  EXPECT_EQ(c.frontierCount(), 2u);
  HyperpathSearchParams p = paramsFor(g, GetParam());
  c.installInto(p);
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "moveX", "moveY", "moveX2", "sink"}));
  expectValidHyperpath(g, g.query(), result);
  EXPECT_GT(result.stats.pruned, 0u);
}

TEST_P(Constraints, HistoryConstraintForbidsOncePreHasAppeared) {
  const NamedGraph g = twoThreads();
  ExpansionConstraints c;
  c.addHistory(g.vertex("X2"), g.vertex("Y2"));  // no Y2 once X2 has existed, even after it left
  HyperpathSearchParams p = paramsFor(g, GetParam());
  c.installInto(p);
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "moveY", "moveX", "moveX2", "sink"}));
  EXPECT_EQ(c.historyCount(), 1u);
  EXPECT_TRUE(c.historyRelevant(g.vertex("X2")));
  EXPECT_FALSE(c.historyRelevant(g.vertex("Y2")));
}

TEST_P(Constraints, ConstraintsChain) {
  const NamedGraph g = twoThreads();
  ExpansionConstraints c;
  c.addHistory(g.vertex("X2"), g.vertex("Y2"));
  c.addHistory(g.vertex("Y2"), g.vertex("X3"));  // Y2 (a post above) is a pre here
  HyperpathSearchParams p = paramsFor(g, GetParam());
  c.installInto(p);
  // Y2 must come before X2, X3 may not come after Y2, and X3 needs X2: no order is left.
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
}

TEST_P(Constraints, InstallChainsWithAnExistingFilter) {
  const NamedGraph g = twoThreads();
  HyperpathSearchParams p = paramsFor(g, GetParam());
  p.allowed = [&g](const HyperpathState&, HyperarcId a) { return a != g["moveX2"]; };
  ExpansionConstraints c;
  c.addFrontier(g.vertex("X"), g.vertex("Y2"));
  c.installInto(p);
  EXPECT_EQ(findHyperpath(g.graph, g.query(), p).status, HyperpathStatus::kExhausted);
}

// The same frontier reached through histories that differ in a history constraint's pre must not
// count as one state: the first history (through P) is a dead end, the second is not.
NamedGraph reconvergingGraph() {
  NamedGraph g;
  g.arc("source", {"src"}, {"S"});
  g.arc("viaP", {"S"}, {"P"});
  g.arc("PtoF", {"P"}, {"F"});
  g.arc("direct", {"S"}, {"F"});
  g.arc("finish", {"F"}, {"G"});
  g.arc("sink", {"G"}, {"sink"});
  return g;
}

TEST_P(Constraints, HistoryRelevantVerticesKeepReconvergingHistoriesApart) {
  const NamedGraph g = reconvergingGraph();
  ExpansionConstraints c;
  c.addHistory(g.vertex("P"), g.vertex("G"));
  HyperpathSearchParams p{.algorithm = GetParam()};
  p.arcCost = [&g](HyperarcId a) { return a == g["direct"] ? 5.0 : 1.0; };  // the detour looks best
  c.installInto(p);
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "direct", "finish", "sink"}));

  // Without telling the search which vertices matter, {F} after P shadows {F} without P.
  HyperpathSearchParams blind{.algorithm = GetParam()};
  blind.arcCost = p.arcCost;
  blind.allowed = [&c](const HyperpathState& s, HyperarcId a) { return c.allows(s, a); };
  EXPECT_EQ(findHyperpath(g.graph, g.query(), blind).status, HyperpathStatus::kExhausted);
}

TEST(ExpansionConstraints, FrontierConstraintIgnoresWhatTheArcConsumes) {
  NamedGraph g;
  g.arc("source", {"src"}, {"X"});
  g.arc("move", {"X"}, {"Y"});
  g.arc("sink", {"Y"}, {"sink"});
  ExpansionConstraints c;
  c.addFrontier(g.vertex("X"), g.vertex("Y"));  // X leaves the frontier with this very step
  HyperpathSearchParams p;
  c.installInto(p);
  EXPECT_TRUE(findHyperpath(g.graph, g.query(), p).found());
  c.clear();
  EXPECT_TRUE(c.empty());
}

}  // namespace
}  // namespace dash
