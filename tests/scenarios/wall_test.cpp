// Wall: each wall cuts exactly the handover between the two neighbours beside it, so the lazy
// assumption "every neighbour handover is feasible" is wrong for some objects, whose real chain is
// longer than the ring suggests.
#include <gtest/gtest.h>

#include <cstdlib>

#include "engine/collision/collision_context.h"
#include "engine/scenarios/handover_graph.h"
#include "scenario_test_util.h"

namespace dash {
namespace {

std::vector<int> wallGaps(const Scene& scene) {
  std::vector<int> gaps;
  for (const auto& o : scene.obstacles) {
    if (o.id.rfind("wall_", 0) == 0) gaps.push_back(std::atoi(o.id.c_str() + 5));
  }
  return gaps;
}

/// Least handovers on the ring if every neighbour pair could hand over.
int ringDistance(int a, int b, int robots) {
  const int d = std::abs(a - b) % robots;
  return std::min(d, robots - d);
}

TEST(Wall, WallsCutExactlyTheirNeighbourHandover) {
  HandoverSearch wide;  // look harder than the generator: round the wall's ends and over it
  wide.across = {0.0, -0.3, 0.3, -0.6, 0.6, -0.9, 0.9, -1.2, 1.2};
  wide.heights = {0.35, 0.6, 0.9, 1.2};
  for (const auto& kv : std::vector<test::KeyValues>{{}, {{"walls", "3"}}, {{"robots", "12"}, {"walls", "5"}}}) {
    const auto g = test::generate("wall", kv, 4);
    const int robots = static_cast<int>(g.scene.robots.size());
    const std::vector<int> gaps = wallGaps(g.scene);
    ASSERT_FALSE(gaps.empty());
    const CollisionWorld world(g.scene);
    CollisionContext context(world);
    for (int r = 0; r < robots; ++r) {
      const int n = (r + 1) % robots;
      const bool walled = std::find(gaps.begin(), gaps.end(), r) != gaps.end();
      EXPECT_EQ(g.report.graph.linked(r, n), !walled) << "robots " << r << "-" << n;
      if (walled) {
        EXPECT_FALSE(findHandover(world, context, r, n, 0, wide).has_value()) << r << "-" << n;
      }
    }
  }
}

// Whenever the long arc holds more than robots/2 + 1 robots (robots >= 4 walls - 1), the shortest
// route on the ring as the lazy planner sees it crosses a wall for some objects.
TEST(Wall, LazyNeighbourAssumptionFails) {
  for (const auto& [robots, walls] : std::vector<std::pair<int, int>>{{8, 1}, {8, 2}, {12, 3}, {32, 6}, {5, 1}}) {
    const auto g = test::generate(
        "wall",
        {{"robots", std::to_string(robots)}, {"walls", std::to_string(walls)}, {"objects", std::to_string(robots)}}, 2);
    int longer = 0;
    for (const auto& t : g.report.transfers) {
      ASSERT_EQ(t.start_robots.size(), 1u);
      ASSERT_EQ(t.goal_robots.size(), 1u);
      ASSERT_GE(t.min_handovers, 1);
      const int assumed = ringDistance(t.start_robots[0], t.goal_robots[0], robots);
      EXPECT_GE(t.min_handovers, assumed);
      if (t.min_handovers > assumed) ++longer;
    }
    EXPECT_GT(longer, 0) << robots << " robots, " << walls << " walls";
  }
}

TEST(Wall, RobotsBesideAWallSendToEachOtherTheLongWay) {
  const auto g = test::generate("wall", {{"objects", "8"}}, 6);  // 8 robots, 1 wall, one object each
  const int gap = wallGaps(g.scene).at(0);
  for (const auto& t : g.report.transfers) {
    if (t.start_robots[0] == gap) {
      EXPECT_EQ(t.goal_robots[0], (gap + 1) % 8);
      EXPECT_EQ(t.min_handovers, 7);
    }
  }
}

}  // namespace
}  // namespace dash
