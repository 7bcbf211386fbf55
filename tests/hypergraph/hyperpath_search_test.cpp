#include "engine/hypergraph/hyperpath_search.h"

#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <map>
#include <set>

#include "tests/hypergraph/test_graphs.h"

namespace dash {
namespace {

using testing::expectValidHyperpath;
using testing::handoverGraph;
using testing::NamedGraph;
using Names = std::vector<std::string>;

class BothSearches : public ::testing::TestWithParam<HyperpathAlgorithm> {
 protected:
  HyperpathSearchParams params() const { return {.algorithm = GetParam()}; }
};

INSTANTIATE_TEST_SUITE_P(Hyperpath, BothSearches,
                         ::testing::Values(HyperpathAlgorithm::kGreedy, HyperpathAlgorithm::kBestFirst),
                         [](const auto& info) {
                           return info.param == HyperpathAlgorithm::kGreedy ? "Greedy" : "BestFirst";
                         });

TEST_P(BothSearches, FindsTheHandoverPlan) {
  const NamedGraph g = handoverGraph();
  const HyperpathResult result = findHyperpath(g.graph, g.query(), params());
  ASSERT_EQ(result.status, HyperpathStatus::kFound);
  EXPECT_EQ(g.names(result), (Names{"source", "pick1", "handover12", "place2", "sink"}));
  expectValidHyperpath(g, g.query(), result);
  // The handover needs the object from the pick and R2 from the start.
  EXPECT_EQ(result.steps[1].dependsOn, (std::vector<std::size_t>{0}));
  EXPECT_EQ(result.steps[2].dependsOn, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(result.steps[3].dependsOn, (std::vector<std::size_t>{2}));
  EXPECT_EQ(result.steps[4].dependsOn, (std::vector<std::size_t>{3}));
  EXPECT_DOUBLE_EQ(result.cost, 4.0);  // unit arc costs, sink included, source not
}

TEST_P(BothSearches, InfeasibleWithCyclesEndsExhausted) {
  const NamedGraph g = handoverGraph(/*reachableGoal=*/false);
  const HyperpathResult result = findHyperpath(g.graph, g.query(), params());
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
  EXPECT_TRUE(result.steps.empty());
  // States: {R1,R2,O_s}, {R1+O,R2}, {R1,R2+O}: each expanded once.
  EXPECT_EQ(result.stats.statesVisited, 3u);
  EXPECT_EQ(result.stats.expansions, 3u);
  EXPECT_EQ(result.stats.duplicates, 2u);  // placing back and handing back return to seen states
}

// A choice that looks best leads to a dead end two steps later; the search must back out of it.
NamedGraph deadEndGraph() {
  NamedGraph g;
  g.arc("source", {"src"}, {"A"});
  g.arc("toB", {"A"}, {"B"});
  g.arc("toD", {"B"}, {"D"});  // D has no way on
  g.arc("toC", {"A"}, {"C"});
  g.arc("toG", {"C"}, {"G"});
  g.arc("sink", {"G"}, {"sink"});
  return g;
}

TEST_P(BothSearches, BacksOutOfADeadEnd) {
  NamedGraph g = deadEndGraph();
  HyperpathSearchParams p = params();
  const std::map<VertexId, double> h{{g.vertex("B"), 0.0}, {g.vertex("D"), 0.0}, {g.vertex("C"), 5.0}};
  p.costToGo = [h](VertexId v) { return h.contains(v) ? h.at(v) : 0.0; };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_EQ(result.status, HyperpathStatus::kFound);
  EXPECT_EQ(g.names(result), (Names{"source", "toC", "toG", "sink"}));
  expectValidHyperpath(g, g.query(), result);
  if (GetParam() == HyperpathAlgorithm::kGreedy) {
    EXPECT_EQ(result.stats.backtracks, 2u);  // out of D, then out of B
  }
}

TEST(GreedySearch, FollowsThePriorityHook) {
  NamedGraph g = deadEndGraph();
  HyperpathSearchParams p;
  p.priority = [&g](const HyperpathState&, HyperarcId a) { return a == g["toC"] ? 0.0 : 1.0; };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "toC", "toG", "sink"}));
  EXPECT_EQ(result.stats.backtracks, 0u);
  EXPECT_EQ(result.stats.expansions, 2u);  // {A}, {C}; at {G} the sink is applicable
}

// X is already at its goal; lifting it looks as good as lifting Y by head cost alone.
NamedGraph finishedWorkGraph() {
  NamedGraph g;
  g.arc("source", {"src"}, {"Xg", "Y"});
  g.arc("liftX", {"Xg"}, {"Xheld"});
  g.arc("dropX", {"Xheld"}, {"Xg"});
  g.arc("liftY", {"Y"}, {"Yheld"});
  g.arc("dropY", {"Yheld"}, {"Yg"});
  g.arc("sink", {"Xg", "Yg"}, {"sink"});
  return g;
}

TEST(GreedySearch, DefaultPrioritiesPostponeUndoingFinishedWork) {
  const NamedGraph g = finishedWorkGraph();
  const std::map<VertexId, double> h{{g.vertex("Xheld"), 1.0}, {g.vertex("Y"), 2.0}, {g.vertex("Yheld"), 1.0}};
  HyperpathSearchParams p;
  p.costToGo = [h](VertexId v) { return h.contains(v) ? h.at(v) : 0.0; };
  for (GreedyPriority rule : {GreedyPriority::kHeadCostToGo, GreedyPriority::kCostToGoDecrease}) {
    p.greedyPriority = rule;
    const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
    ASSERT_TRUE(result.found());
    EXPECT_EQ(g.names(result), (Names{"source", "liftY", "dropY", "sink"}));
  }
  // The same order as a hook is taken literally: liftX wins the tie on id, and is undone later.
  p.priority = [&](const HyperpathState& s, HyperarcId a) {
    double worst = 0.0;
    for (VertexId v : s.topology().head(a)) worst = std::max(worst, p.costToGo(v));
    return 1.0 + worst;
  };
  const HyperpathResult literal = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(literal.found());
  EXPECT_EQ(g.names(literal), (Names{"source", "liftX", "liftY", "dropX", "dropY", "sink"}));
}

TEST(GreedySearch, PostponedStepsAreStillTried) {
  // Y's only way to its goal passes through X's goal spot: X must leave it for a while.
  NamedGraph g;
  g.arc("source", {"src"}, {"Xg", "Y"});
  g.arc("liftX", {"Xg"}, {"Xheld"});
  g.arc("YthroughX", {"Y", "Xheld"}, {"Yg", "Xheld2"});
  g.arc("dropX", {"Xheld2"}, {"Xg"});
  g.arc("sink", {"Xg", "Yg"}, {"sink"});
  HyperpathSearchParams p;
  p.costToGo = [&g](VertexId v) { return v == g.vertex("Xg") || v == g.vertex("Yg") ? 0.0 : 1.0; };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "liftX", "YthroughX", "dropX", "sink"}));
}

TEST(BestFirstSearch, FindsTheCheapestHyperpath) {
  NamedGraph g;
  g.arc("source", {"src"}, {"A"});
  g.arc("short", {"A"}, {"G"});  // one step, expensive
  g.arc("a1", {"A"}, {"M"});
  g.arc("a2", {"M"}, {"G"});
  g.arc("sink", {"G"}, {"sink"});
  HyperpathSearchParams p{.algorithm = HyperpathAlgorithm::kBestFirst};
  p.arcCost = [&g](HyperarcId a) { return a == g["short"] ? 10.0 : 2.0; };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  EXPECT_EQ(g.names(result), (Names{"source", "a1", "a2", "sink"}));
  EXPECT_DOUBLE_EQ(result.cost, 6.0);
}

// A frontier holding two instances of T: each is consumed by a different step, never one twice.
TEST_P(BothSearches, FrontierIsAMultisetAndNoInstanceIsConsumedTwice) {
  NamedGraph g;
  g.arc("source", {"src"}, {"A"});
  g.arc("split", {"A"}, {"B", "C"});
  g.arc("bt", {"B"}, {"T"});
  g.arc("ct", {"C"}, {"T"});
  g.arc("tu", {"T"}, {"U"});
  g.arc("sink", {"T", "U"}, {"sink"});
  HyperpathSearchParams p = params();
  // Make the search want "tu" early; a second T is still needed for the sink.
  p.costToGo = [&g](VertexId v) { return v == g.vertex("U") ? 0.0 : 1.0; };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  expectValidHyperpath(g, g.query(), result);
  const HyperpathStep& sink = result.steps.back();
  const HyperpathStep& tu = result.steps[g.stepIndex(result, "tu")];
  ASSERT_EQ(sink.consumed.size(), 2u);
  EXPECT_NE(sink.consumed[0], tu.consumed[0]);  // the sink's T is the other instance
  EXPECT_EQ(result.steps.size(), 6u);            // source split bt ct tu sink
}

TEST_P(BothSearches, ObserverSeesEachExtendedElementOnce) {
  const NamedGraph g = handoverGraph(/*reachableGoal=*/false);  // explores everything
  HyperpathSearchParams p = params();
  std::map<ExtendedVertexId, ExtendedHyperarcId> vertices;
  std::set<ExtendedHyperarcId> arcs;
  std::size_t vertexCalls = 0, arcCalls = 0;
  p.onExtendedVertex = [&](const ExtendedVertex& v) {
    ++vertexCalls;
    EXPECT_TRUE(vertices.emplace(v.id, v.producedBy).second);
    EXPECT_FALSE(arcs.contains(v.producedBy)) << "vertices are announced before their hyperarc";
  };
  p.onExtendedHyperarc = [&](const ExtendedHyperarc& e) {
    ++arcCalls;
    EXPECT_TRUE(arcs.insert(e.id).second);
    if (e.parent.valid()) {
      EXPECT_TRUE(arcs.contains(e.parent));
    }
    for (ExtendedVertexId i : e.produced) EXPECT_EQ(vertices.at(i), e.id);
    for (ExtendedVertexId i : e.consumed) EXPECT_TRUE(vertices.contains(i));
    EXPECT_EQ(e.produced.size(), g.graph.head(e.hyperarc).size());
  };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
  EXPECT_EQ(vertexCalls, result.stats.extendedVertices);
  EXPECT_EQ(arcCalls, result.stats.extendedHyperarcs);
  EXPECT_EQ(arcCalls, 3u);  // source, pick1, handover12: the other successors repeat a state
  EXPECT_EQ(vertexCalls, 3u + 1u + 2u);
}

TEST_P(BothSearches, StepsNameAnnouncedExtendedHyperarcs) {
  const NamedGraph g = handoverGraph();
  HyperpathSearchParams p = params();
  std::map<ExtendedHyperarcId, HyperarcId> announced;
  p.onExtendedHyperarc = [&](const ExtendedHyperarc& e) { announced.emplace(e.id, e.hyperarc); };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_TRUE(result.found());
  for (const HyperpathStep& step : result.steps) EXPECT_EQ(announced.at(step.extended), step.hyperarc);
}

TEST_P(BothSearches, ExpiredDeadlineStopsAtOnce) {
  const NamedGraph g = handoverGraph();
  HyperpathSearchParams p = params();
  p.deadline = Deadline(-1.0);
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kDeadline);
  EXPECT_EQ(result.stats.expansions, 0u);
}

// A frontier that can grow without bound (A -> A + B): only the stop flag, the depth limit or the
// budget can end the search, and each does.
NamedGraph growingGraph() {
  NamedGraph g;
  g.arc("source", {"src"}, {"A"});
  g.arc("grow", {"A"}, {"A", "B"});
  g.arc("sink", {"Z"}, {"sink"});
  return g;
}

TEST_P(BothSearches, StopFlagEndsAnUnboundedSearch) {
  const NamedGraph g = growingGraph();
  std::atomic<bool> stop{false};
  HyperpathSearchParams p = params();
  p.deadline = Deadline(1e12, &stop);
  std::size_t calls = 0;
  p.allowed = [&](const HyperpathState&, HyperarcId) {
    if (++calls == 100) stop = true;
    return true;
  };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kDeadline);
  EXPECT_LE(result.stats.expansions, 101u);
}

TEST_P(BothSearches, DepthLimitAndBudgetEndAnUnboundedSearch) {
  const NamedGraph g = growingGraph();
  HyperpathSearchParams p = params();
  p.maxDepth = 20;
  HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kBudget);  // cut off, not proven infeasible
  EXPECT_EQ(result.stats.maxDepthReached, 20u);
  p.maxDepth = std::numeric_limits<std::size_t>::max();
  p.maxExpansions = 50;
  result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kBudget);
  EXPECT_EQ(result.stats.expansions, 50u);
}

// The greedy search's memory guard: successors waiting on its depth-first stack.
TEST(GreedySearch, PendingSuccessorsCapEndsTheSearchAsABudget) {
  NamedGraph g;  // two ways to grow from every state: each level of the stack keeps one untried
  g.arc("source", {"src"}, {"A"});
  g.arc("grow B", {"A"}, {"A", "B"});
  g.arc("grow C", {"A"}, {"A", "C"});
  g.arc("sink", {"Z"}, {"sink"});
  HyperpathSearchParams p;
  p.algorithm = HyperpathAlgorithm::kGreedy;
  p.maxDepth = 12;
  HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  ASSERT_EQ(result.status, HyperpathStatus::kBudget);
  const std::size_t uncapped = result.stats.expansions;
  p.maxPendingSuccessors = 3;
  result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kBudget);
  EXPECT_LT(result.stats.expansions, uncapped);
}

TEST_P(BothSearches, AllowedCanForbidTheSink) {
  const NamedGraph g = handoverGraph();
  HyperpathSearchParams p = params();
  p.allowed = [&g](const HyperpathState&, HyperarcId a) { return a != g["sink"]; };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
  EXPECT_GT(result.stats.pruned, 0u);
}

TEST_P(BothSearches, InfiniteCostToGoIsADeadEnd) {
  const NamedGraph g = deadEndGraph();
  HyperpathSearchParams p = params();
  p.costToGo = [&g](VertexId v) {
    return v == g.vertex("C") ? std::numeric_limits<double>::infinity() : 0.0;
  };
  const HyperpathResult result = findHyperpath(g.graph, g.query(), p);
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
}

TEST_P(BothSearches, SameInputSameHyperpath) {
  const NamedGraph g = handoverGraph();
  const HyperpathResult a = findHyperpath(g.graph, g.query(), params());
  const HyperpathResult b = findHyperpath(g.graph, g.query(), params());
  ASSERT_TRUE(a.found() && b.found());
  ASSERT_EQ(a.steps.size(), b.steps.size());
  for (std::size_t s = 0; s < a.steps.size(); ++s) {
    EXPECT_EQ(a.steps[s].extended, b.steps[s].extended);
    EXPECT_EQ(a.steps[s].consumed, b.steps[s].consumed);
  }
}

TEST(HyperpathSearch, BadInputThrows) {
  const NamedGraph g = handoverGraph();
  EXPECT_THROW(findHyperpath(g.graph, {HyperarcId(99), g["sink"]}), InputError);
  HyperpathSearchParams p;
  p.arcCost = [](HyperarcId) { return -1.0; };
  EXPECT_THROW(findHyperpath(g.graph, g.query(), p), InputError);
}

TEST(HyperpathSearch, StatusNames) {
  EXPECT_EQ(toString(HyperpathStatus::kFound), "found");
  EXPECT_EQ(toString(HyperpathStatus::kExhausted), "exhausted");
  EXPECT_EQ(toString(HyperpathStatus::kDeadline), "deadline");
  EXPECT_EQ(toString(HyperpathStatus::kBudget), "budget");
}

}  // namespace
}  // namespace dash
