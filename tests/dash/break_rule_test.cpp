// CBS-MP's probabilistic break rule on its own: forced choices, the growth budget, and the draw.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "engine/dash/break_rule.h"

namespace dash {
namespace {

MotionConflict conflictOf(MotionConflict::Kind kind, std::vector<int> robots, int arcs) {
  MotionConflict c;
  c.kind = kind;
  c.robots = std::move(robots);
  for (int i = 0; i < arcs; ++i) c.arcs.push_back(HyperarcId(static_cast<std::uint32_t>(i)));
  return c;
}

using Decision = BreakRule::Decision;
constexpr auto kMove = MotionConflict::Kind::kMove;
constexpr auto kSchedule = MotionConflict::Kind::kSchedule;
constexpr auto kTransition = MotionConflict::Kind::kTransition;

TEST(BreakRule, NeverGrowsRoadmapsAtProbabilityZero) {
  BreakRule rule(3, {.grow_roadmap_probability = 0.0, .max_roadmap_growths = 8}, 1);
  for (int i = 0; i < 50; ++i) EXPECT_EQ(rule.decide(conflictOf(kSchedule, {0, 1}, 2)).decision, Decision::kGrowTree);
  EXPECT_EQ(rule.treeDecisions(), 50);
  EXPECT_EQ(rule.roadmapDecisions(), 0);
  EXPECT_EQ(rule.growths(0), 0);
}

TEST(BreakRule, GrowsRoadmapsAtProbabilityOneUntilTheBudgetIsSpent) {
  BreakRule rule(3, {.grow_roadmap_probability = 1.0, .max_roadmap_growths = 3}, 1);
  for (int i = 0; i < 3; ++i) {
    const BreakRule::Choice c = rule.decide(conflictOf(kMove, {2, 0, 2}, 1));
    ASSERT_EQ(c.decision, Decision::kGrowRoadmaps);
    EXPECT_EQ(c.robots, (std::vector<int>{2, 0}));  // each robot once, in the conflict's order
  }
  EXPECT_EQ(rule.growths(0), 3);
  EXPECT_EQ(rule.growths(1), 0);
  EXPECT_EQ(rule.growths(2), 3);
  EXPECT_EQ(rule.decide(conflictOf(kMove, {0, 2}, 1)).decision, Decision::kGrowTree);
  // Robot 1 still has budget: a conflict involving it grows only its roadmaps.
  const BreakRule::Choice c = rule.decide(conflictOf(kMove, {0, 1}, 1));
  ASSERT_EQ(c.decision, Decision::kGrowRoadmaps);
  EXPECT_EQ(c.robots, std::vector<int>{1});
  EXPECT_EQ(rule.roadmapDecisions(), 4);
  EXPECT_EQ(rule.treeDecisions(), 1);
}

TEST(BreakRule, TransitionConflictsGrowTheTree) {
  BreakRule rule(2, {.grow_roadmap_probability = 1.0, .max_roadmap_growths = 8}, 1);
  EXPECT_EQ(rule.decide(conflictOf(kTransition, {0}, 1)).decision, Decision::kGrowTree);
  EXPECT_EQ(rule.growths(0), 0);
}

TEST(BreakRule, NothingToForbidGrowsRoadmapsOrKillsTheNode) {
  BreakRule rule(2, {.grow_roadmap_probability = 0.0, .max_roadmap_growths = 1}, 1);
  EXPECT_EQ(rule.decide(conflictOf(kSchedule, {1}, 0)).decision, Decision::kGrowRoadmaps);
  EXPECT_EQ(rule.decide(conflictOf(kSchedule, {1}, 0)).decision, Decision::kDeadNode);
  EXPECT_EQ(rule.decide(conflictOf(kSchedule, {}, 0)).decision, Decision::kDeadNode);
}

TEST(BreakRule, DrawsWithTheGivenProbabilityReproducibly) {
  auto run = [](std::uint64_t seed) {
    BreakRule rule(1, {.grow_roadmap_probability = 0.3, .max_roadmap_growths = 1 << 30}, seed);
    std::vector<Decision> out;
    for (int i = 0; i < 4000; ++i) out.push_back(rule.decide(conflictOf(kMove, {0}, 1)).decision);
    return out;
  };
  const std::vector<Decision> a = run(7);
  const auto grows = std::count(a.begin(), a.end(), Decision::kGrowRoadmaps);
  EXPECT_GT(grows, 4000 * 0.26);
  EXPECT_LT(grows, 4000 * 0.34);
  EXPECT_EQ(run(7), a);
  EXPECT_NE(run(8), a);
}

}  // namespace
}  // namespace dash
