// The collision queries with the covers' fast reject (cover_check.h) and without it give the same
// answer and the same report (which pair, where along a segment) on random queries in scenes of every
// family: configurations, one robot's segments, motions among parked robots, simultaneous motions.
#include <gtest/gtest.h>

#include <cstdio>
#include <functional>

#include "engine/collision/cover_check.h"
#include "engine/collision/segment_queries.h"
#include "tests/collision/cover_test_util.h"

namespace dash {
namespace {

struct Answer {
  bool collides = false;
  CollisionReport report;
  bool operator==(const Answer& o) const {
    return collides == o.collides && report.a == o.report.a && report.b == o.report.b &&
           report.segment_fraction == o.report.segment_fraction;
  }
};

std::string describeAnswer(const Answer& a, const Scene& scene) {
  return a.collides ? describe(a.report, scene) + " at " + std::to_string(a.report.segment_fraction) : "free";
}

/// The query's answer with the fast path on and off.
template <class Query>
std::pair<Answer, Answer> bothWays(Query query) {
  std::pair<Answer, Answer> out;
  setCoverFastPath(true);
  out.first.collides = query(&out.first.report);
  setCoverFastPath(false);
  out.second.collides = query(&out.second.report);
  setCoverFastPath(true);
  return out;
}

/// A motion of robot r from a random configuration by up to `reach` rad (or reach / 4 m) per joint.
RobotMotion randomMotion(const Scene& scene, int r, Rng& rng, double reach) {
  RobotMotion m;
  m.start = {.robot = r, .q = test::randomState(scene, r, rng), .held = test::randomHeld(scene, rng, 0.3)};
  const RobotModel& model = *scene.robots[static_cast<std::size_t>(r)].model;
  const double scale = model.kinematics == KinematicsKind::kUrDh ? reach : 0.25 * reach;
  m.q_end = m.start.q;
  for (int j = 0; j < model.dof(); ++j) {
    m.q_end[j] =
        std::clamp(m.q_end[j] + rng.uniform(-scale, scale), model.limits.position_min[j], model.limits.position_max[j]);
  }
  return m;
}

struct Counts {
  int queries = 0, colliding = 0;
};

/// One random query of each kind; EXPECTs the same answer both ways.
void compareOnce(const CollisionWorld& world, CollisionContext& context, Rng& rng, Counts& counts) {
  const Scene& scene = world.scene();
  const ObjectLayout start = ObjectLayout::atStart(scene);
  const int n = world.robotCount();
  const int r = static_cast<int>(rng.integer(0, n - 1));
  RobotMotion m = randomMotion(scene, r, rng, 1.0);
  ObjectLayout layout = start;
  if (m.start.held.holding()) layout.remove(m.start.held.object);
  std::vector<RobotState> parked;
  for (int p = 0; p < n; ++p)
    if (p != r) parked.push_back({.robot = p, .q = test::randomState(scene, p, rng)});
  const std::vector<std::pair<std::string, std::function<bool(CollisionReport*)>>> queries = {
      {"robotInCollision",
       [&](CollisionReport* rep) { return robotInCollision(world, context, m.start, layout, rep); }},
      {"robotsAmongParked",
       [&](CollisionReport* rep) {
         return robotsAmongParked(world, context, std::span<const RobotState>(&m.start, 1), parked, layout, rep);
       }},
      {"segmentInCollision",
       [&](CollisionReport* rep) { return segmentInCollision(world, context, m.start, m.q_end, layout, rep); }},
      {"motionsAmongParked", [&](CollisionReport* rep) {
         return motionsAmongParked(world, context, std::span<const RobotMotion>(&m, 1), parked, start, rep);
       }}};
  for (const auto& [name, query] : queries) {
    const auto [fast, exact] = bothWays(query);
    EXPECT_TRUE(fast == exact) << name << " in " << scene.name << ": fast " << describeAnswer(fast, scene) << ", exact "
                               << describeAnswer(exact, scene);
    ++counts.queries;
    counts.colliding += exact.collides ? 1 : 0;
  }
  if (n < 2) return;
  // Two robots moving at once, robot against robot only (conflict resolution) and everything.
  const int r2 = (r + 1 + static_cast<int>(rng.integer(0, n - 2))) % n;
  RobotMotion pair[2] = {m, randomMotion(scene, r2, rng, 1.0)};
  if (pair[1].start.held.object == pair[0].start.held.object) pair[1].start.held = {};
  for (const CheckScope scope : {CheckScope::kRobotsOnly, CheckScope::kAll}) {
    const auto [fast, exact] = bothWays([&](CollisionReport* rep) {
      return motionsInCollision(world, context, pair, ObjectLayout::empty(scene), rep, {.scope = scope});
    });
    EXPECT_TRUE(fast == exact) << "motionsInCollision in " << scene.name << ": fast " << describeAnswer(fast, scene)
                               << ", exact " << describeAnswer(exact, scene);
    ++counts.queries;
    counts.colliding += exact.collides ? 1 : 0;
  }
}

TEST(CoverQueries, AnswersAndReportsAreTheSameWithTheFastPathOnAndOffInEveryFamily) {
  for (const auto& fs : test::familyScenes()) {
    const CollisionWorld world(*fs.scene, {.clearance = kDefaultPlanningClearance});
    CollisionContext context(world);
    Rng rng(7);
    Counts counts;
    for (int i = 0; i < 1500 && !HasFailure(); ++i) compareOnce(world, context, rng, counts);
    std::printf("%-10s %d queries, %d in collision\n", fs.family.c_str(), counts.queries, counts.colliding);
    EXPECT_GT(counts.colliding, counts.queries / 20) << fs.family;
    EXPECT_LT(counts.colliding, counts.queries * 9 / 10) << fs.family;
  }
}

TEST(CoverQueries, TheSwitchTurnsTheFastPathOffAndOn) {
  setCoverFastPath(false);
  EXPECT_FALSE(coverFastPath());
  setCoverFastPath(true);
  EXPECT_TRUE(coverFastPath());
}

}  // namespace
}  // namespace dash
