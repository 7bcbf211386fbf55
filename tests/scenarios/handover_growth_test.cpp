// Sorting: the least number of handovers an object needs, computed from the geometry (robot graph:
// an edge where two robots have a collision-free mid-air handover pose; an object's minimum: the
// shortest path from the robots that can grasp its start to those that can grasp its goal), grows
// with the number of robots.
#include <gtest/gtest.h>

#include <algorithm>

#include "scenario_test_util.h"

namespace dash {
namespace {

TEST(SortingHandovers, MinimumGrowsWithRobots) {
  int previous = 0;
  for (const int robots : {2, 4, 8, 16, 32}) {
    SCOPED_TRACE("robots " + std::to_string(robots));
    const auto g =
        test::generate("sorting", {{"robots", std::to_string(robots)}, {"objects", std::to_string(robots)}}, 3);
    ASSERT_EQ(static_cast<int>(g.report.transfers.size()), robots);
    int least = 1 << 30, most = 0;
    for (const auto& t : g.report.transfers) {
      // Only the object's own robot reaches its start, only the box's robot its goal.
      ASSERT_EQ(t.start_robots.size(), 1u);
      ASSERT_EQ(t.goal_robots.size(), 1u);
      least = std::min(least, t.min_handovers);
      most = std::max(most, t.min_handovers);
    }
    // Cross sorting on a ring whose only handover edges join neighbours: R/2 handovers each.
    EXPECT_EQ(least, robots / 2);
    EXPECT_EQ(most, robots / 2);
    EXPECT_GT(least, previous);
    previous = least;
  }
}

TEST(SortingHandovers, GraphIsTheRingOfNeighbours) {
  for (const int robots : {3, 4, 5, 8, 13}) {
    const auto g = test::generate("sorting", {{"robots", std::to_string(robots)}, {"objects", "1"}}, 1);
    const auto& adjacent = g.report.graph.adjacent;
    ASSERT_EQ(static_cast<int>(adjacent.size()), robots);
    for (int r = 0; r < robots; ++r) {
      const std::vector<int> expected = [&] {
        std::vector<int> n = {(r + 1) % robots, (r + robots - 1) % robots};
        std::sort(n.begin(), n.end());
        n.erase(std::unique(n.begin(), n.end()), n.end());
        return n;
      }();
      EXPECT_EQ(adjacent[static_cast<std::size_t>(r)], expected) << "robots " << robots << " robot " << r;
    }
  }
}

TEST(SortingHandovers, TwoRobotsHandOverOnce) {
  const auto g = test::generate("sorting", {{"robots", "2"}, {"objects", "6"}}, 9);
  ASSERT_EQ(g.report.graph.edges.size(), 1u);
  for (const auto& t : g.report.transfers) EXPECT_EQ(t.min_handovers, 1);
}

}  // namespace
}  // namespace dash
