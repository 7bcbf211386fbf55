// Conflict resolution's checks on two lanes (issue 38 item 3): the same answers, and the same collision
// counters, as on one, over random schedules of six arms where conflicts are common.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

#include "engine/conflict/check_pool.h"
#include "engine/conflict/schedule_checker.h"
#include "tests/collision/cover_test_util.h"

namespace dash {
namespace {

/// Robot r's timeline: `points` random configurations 1-2 s apart from `start`, holding a random
/// object over part of it at random.
RobotTimeline randomTimeline(const Scene& scene, int r, Rng& rng, double start, int points) {
  RobotTimeline t(r, scene.robots[static_cast<std::size_t>(r)].home);
  double at = start;
  for (int i = 0; i < points; ++i) t.append(at += rng.uniform(1.0, 2.0), test::randomState(scene, r, rng));
  const HeldObject held = test::randomHeld(scene, rng, 0.4);
  if (held.holding()) t.grasp(rng.uniform(start, at), held);
  return t;
}

std::string text(const std::optional<ScheduleConflict>& c) {
  if (!c) return "free";
  return std::to_string(c->t) + " robot " + std::to_string(c->robot) + " other " + std::to_string(c->other) +
         " object " + std::to_string(c->object);
}

TEST(ScheduleCheckerLanes, TwoLanesGiveTheSameConflictsAndCountersAsOne) {
  const Scene scene = generateScenario("sorting", {{"robots", "6"}, {"objects", "12"}}, 1, test::library());
  const CollisionWorld world(scene, {.clearance = kDefaultPlanningClearance});
  CollisionContext one_context(world), two_context(world);
  ScheduleChecker one(world, one_context, 1), two(world, two_context, 2);
  ASSERT_EQ(one.lanes(), 1u);
  ASSERT_EQ(two.lanes(), 2u);
  const ObjectTimeline objects(ObjectLayout::atStart(scene));
  Rng rng(38);
  int conflicts = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<RobotTimeline> timelines;
    for (int r = 0; r < 6; ++r) timelines.push_back(randomTimeline(scene, r, rng, 0.0, 6));
    for (int again = 0; again < 3; ++again) {  // the standing-still verdicts are looked up the second time
      const int r = static_cast<int>(rng.integer(0, 5));
      RobotTimeline moving = timelines[static_cast<std::size_t>(r)];
      const double from = moving.end();
      moving.append(from + rng.uniform(0.5, 3.0), test::randomState(scene, r, rng));
      const auto a = one.check(moving, from, kForever, timelines, objects);
      const auto b = two.check(moving, from, kForever, timelines, objects);
      EXPECT_EQ(text(a), text(b)) << "trial " << trial;
      conflicts += a.has_value();
      const auto a0 = one.check(timelines[static_cast<std::size_t>(r)], 0.0, kForever, timelines, objects);
      const auto b0 = two.check(timelines[static_cast<std::size_t>(r)], 0.0, kForever, timelines, objects);
      EXPECT_EQ(text(a0), text(b0)) << "trial " << trial << " from 0";
      conflicts += a0.has_value();
    }
    EXPECT_EQ(two_context.counters().configuration_checks, one_context.counters().configuration_checks) << trial;
    EXPECT_EQ(two_context.counters().segment_checks, one_context.counters().segment_checks) << trial;
    EXPECT_EQ(two.piecesApart(), one.piecesApart());
    EXPECT_EQ(two.piecesChecked(), one.piecesChecked());
  }
  EXPECT_GT(conflicts, 30);
  EXPECT_GT(one.piecesChecked(), 200u);
}

// Each lane's share runs exactly once per run, on its worker or on the caller when the worker is late,
// and an exception of a worker's lane reaches the caller.
TEST(CheckPool, EveryLaneRunsOncePerRunAndItsExceptionReachesTheCaller) {
  CheckPool pool(2);
  std::atomic<int> runs[2] = {0, 0};
  std::atomic<int> on_worker = 0;
  const std::thread::id caller = std::this_thread::get_id();
  // Lane 0 slow: the worker takes lane 1 (at least sometimes, even on a busy machine).
  for (int i = 0; i < 200; ++i)
    pool.run([&](std::size_t lane) {
      if (lane == 0) std::this_thread::sleep_for(std::chrono::milliseconds(1));
      ++runs[lane];
      if (std::this_thread::get_id() != caller) ++on_worker;
    });
  EXPECT_GT(on_worker.load(), 0) << "the worker never took its share";
  // Lane 0 fast: the caller mostly takes lane 1 itself.
  for (int i = 0; i < 4800; ++i) pool.run([&](std::size_t lane) { ++runs[lane]; });
  EXPECT_EQ(runs[0].load(), 5000);
  EXPECT_EQ(runs[1].load(), 5000);
  EXPECT_THROW(pool.run([](std::size_t lane) {
                 if (lane == 1) throw std::runtime_error("lane 1");
               }),
               std::runtime_error);
  pool.run([&](std::size_t lane) { ++runs[lane]; });
  EXPECT_EQ(runs[1].load(), 5001);
  EXPECT_EQ(checkLanes(1), 1u);
  EXPECT_EQ(checkLanes(3), 3u);
  EXPECT_EQ(checkLanes(1000), kMaxCheckLanes);
  EXPECT_GE(checkLanes(0), 1u);
  EXPECT_LE(checkLanes(0), 2u);
}

}  // namespace
}  // namespace dash
