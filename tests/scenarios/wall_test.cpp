// Wall: each wall cuts exactly the handover between the two neighbours beside it, so the lazy
// assumption "every neighbour handover is feasible" is wrong for some objects, whose real chain is
// longer than the ring suggests.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdlib>
#include <set>
#include <tuple>

#include "engine/collision/collision_context.h"
#include "engine/collision/scene_check.h"
#include "engine/scenarios/handover_graph.h"
#include "engine/scene/scene_json.h"
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

// Up to robots/2 walls, scenes are what the generator made before it took more walls: the JSON of
// these scenes (12 objects), hashed (FNV-1a 64) from files written by that generator.
TEST(Wall, ScenesWithUpToHalfAsManyWallsAsRobotsAreUnchanged) {
  struct Golden {
    int robots, walls;
    std::uint64_t seed, fnv;
  };
  const std::vector<Golden> golden = {
      {8, 2, 2, 0x7ae291143a06edf6ULL}, {8, 3, 2, 0x61bff12f12013b64ULL}, {8, 4, 3, 0x1890ba73ce464407ULL},
      {9, 4, 1, 0xb4b460eb86fc0726ULL}, {7, 3, 3, 0x85103869aa6ec351ULL}, {12, 6, 3, 0xcdc000209a702d19ULL},
      {5, 2, 3, 0x948c291c17f70642ULL}, {4, 2, 1, 0x0e92a65f93ca8a54ULL},
  };
  for (const Golden& g : golden) {
    const std::string json = sceneToJson(
        test::generate("wall",
                       {{"robots", std::to_string(g.robots)}, {"walls", std::to_string(g.walls)}, {"objects", "12"}},
                       g.seed)
            .scene);
    std::uint64_t h = 0xcbf29ce484222325ULL;
    for (const unsigned char c : json) h = (h ^ c) * 0x100000001b3ULL;
    EXPECT_EQ(h, g.fnv) << g.robots << " robots, " << g.walls << " walls, seed " << g.seed;
  }
}

// More walls than robots/2 (up to robots - 1): the first robots/2 stand every other gap as before,
// the rest fill the remaining gaps; a robot walled in on both sides sorts its objects into its own
// box, every other robot still sends along its arc. The scenes pass check-scene.
TEST(Wall, MoreWallsThanHalfTheRobotsSplitPairsIntoSingleArms) {
  for (const auto& [robots, walls, seed] :
       std::vector<std::tuple<int, int, std::uint64_t>>{{8, 5, 1}, {8, 6, 2}, {8, 6, 7}, {8, 7, 3}, {5, 4, 4}, {4, 3, 5}}) {
    SCOPED_TRACE(std::to_string(robots) + " robots, " + std::to_string(walls) + " walls, seed " + std::to_string(seed));
    const auto g = test::generate(
        "wall",
        {{"robots", std::to_string(robots)}, {"walls", std::to_string(walls)}, {"objects", std::to_string(2 * robots)}},
        seed);
    ASSERT_TRUE(g.report.ok()) << g.report.problems.front();
    const Scene scene = parseScene(sceneToJson(g.scene), test::library());
    const std::vector<std::string> problems = findSceneProblems(scene);
    EXPECT_TRUE(problems.empty()) << problems.front();

    const std::vector<int> gaps = wallGaps(scene);
    const std::set<int> walled(gaps.begin(), gaps.end());
    ASSERT_EQ(walled.size(), static_cast<std::size_t>(walls));
    // robots/2 of the walls stand every other gap.
    bool every_other = false;
    for (int o = 0; o < robots && !every_other; ++o) {
      every_other = true;
      for (int k = 0; k < robots / 2; ++k) every_other &= walled.count((o + 2 * k) % robots) > 0;
    }
    EXPECT_TRUE(every_other);
    for (int r = 0; r < robots; ++r) {
      EXPECT_EQ(g.report.graph.linked(r, (r + 1) % robots), walled.count(r) == 0) << "robots " << r << "-" << r + 1;
    }
    int alone = 0;
    for (const auto& t : g.report.transfers) {
      ASSERT_EQ(t.start_robots.size(), 1u);
      ASSERT_EQ(t.goal_robots.size(), 1u);
      const int s = t.start_robots[0];
      const bool single = walled.count(s) > 0 && walled.count((s + robots - 1) % robots) > 0;
      if (single) {
        ++alone;
        EXPECT_EQ(t.goal_robots[0], s) << "robot " << s << " is walled in";
        EXPECT_EQ(t.min_handovers, 0);
      } else {
        EXPECT_NE(t.goal_robots[0], s) << "robot " << s;
        EXPECT_GE(t.min_handovers, 1);
      }
    }
    // walls - robots/2 extra walls each wall in at least one more robot.
    EXPECT_GE(alone, 2 * (walls - robots / 2));
  }
}

}  // namespace
}  // namespace dash
