// The paper's scale (16 robots, 64 objects, cross sorting with handovers; about 10^5 hyperarcs) and
// a plan of about 500 steps. Timing goals belong in benchmarks; this checks the plan and prints the
// time.
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "tests/hypergraph/task_like_graph.h"

namespace dash {
namespace {

using testing::buildTaskLike;
using testing::TaskLike;

void report(const char* name, const TaskLike& t, const HyperpathResult& r) {
  std::printf("[ scale    ] %s: %zu vertices, %zu hyperarcs: %s, %zu steps, %zu expansions, %zu backtracks, "
              "%zu states, %.3f s\n",
              name, t.graph.vertexCount(), t.graph.hyperarcCount(), std::string(toString(r.status)).c_str(),
              r.steps.size(), r.stats.expansions, r.stats.backtracks, r.stats.statesVisited, r.stats.seconds);
}

class HyperpathScale : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    big_ = std::make_unique<TaskLike>(buildTaskLike(/*robots=*/16, /*objects=*/64, /*grasps=*/7, /*handoverReach=*/1));
  }
  static void TearDownTestSuite() { big_.reset(); }
  static std::unique_ptr<TaskLike> big_;
};
std::unique_ptr<TaskLike> HyperpathScale::big_;

TEST_F(HyperpathScale, GreedyPlansSixtyFourObjectsWithSixteenRobots) {
  const TaskLike& t = *big_;
  EXPECT_GT(t.graph.hyperarcCount(), 90000u);
  for (GreedyPriority rule : {GreedyPriority::kHeadCostToGo, GreedyPriority::kCostToGoDecrease}) {
    HyperpathSearchParams p;
    p.costToGo = [&t](VertexId v) { return t.costToGo[v.value()]; };
    p.greedyPriority = rule;
    const HyperpathResult result = findHyperpath(t.graph, t.query, p);
    report(rule == GreedyPriority::kHeadCostToGo ? "greedy, head costToGo" : "greedy, costToGo decrease", t, result);
    ASSERT_EQ(result.status, HyperpathStatus::kFound);
    EXPECT_GT(result.steps.size(), 500u);
    // Every object ends at its goal: the sink consumed an instance of each goal vertex.
    EXPECT_EQ(result.steps.back().consumed.size(), static_cast<std::size_t>(t.objects));
    // A good heuristic on this problem never needs to back out.
    EXPECT_EQ(result.stats.backtracks, 0u);
  }
}

TEST_F(HyperpathScale, BestFirstPlansASmallerInstance) {
  const TaskLike t = buildTaskLike(/*robots=*/4, /*objects=*/4, /*grasps=*/2, /*handoverReach=*/1);
  HyperpathSearchParams p{.algorithm = HyperpathAlgorithm::kBestFirst};
  p.costToGo = [&t](VertexId v) { return t.costToGo[v.value()]; };
  p.heuristic = FrontierHeuristic::kSum;
  const HyperpathResult result = findHyperpath(t.graph, t.query, p);
  report("best-first, sum", t, result);
  ASSERT_EQ(result.status, HyperpathStatus::kFound);
  EXPECT_EQ(result.steps.back().consumed.size(), static_cast<std::size_t>(t.objects));
}

}  // namespace
}  // namespace dash
