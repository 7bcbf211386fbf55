// The scheduler's continuous-time check: time is cut at every breakpoint of the two timelines of each
// pair, and at the instants the plan validator pointed at (alsoCheckAt), so the robots at exactly those
// instants are checked; a standing robot's verdict over another's segment is kept.
#include <gtest/gtest.h>

#include "engine/conflict/schedule_checker.h"
#include "tests/conflict/two_arms.h"

namespace dash {
namespace {

struct TwoArms : testing::TwoArms {
  ObjectTimeline objects{layout};
  std::vector<RobotTimeline> timelines{RobotTimeline(0, scene.robots[0].home), RobotTimeline(1, scene.robots[1].home)};

  std::uint64_t checksOver(ScheduleChecker& checker, double from, double until) {
    const std::uint64_t before = context.counters().configuration_checks;
    EXPECT_FALSE(checker.check(timelines[0], from, until, timelines, objects).has_value());
    return context.counters().configuration_checks - before;
  }
};

TEST(ScheduleChecker, BothArmsStillAtHomeAreClear) {
  TwoArms arms;
  ScheduleChecker checker(arms.world, arms.context);
  EXPECT_GT(arms.checksOver(checker, 0.0, 10.0), 0u);
}

TEST(ScheduleChecker, AnInstantToCheckCutsTheIntervalsItFallsIn) {
  TwoArms arms;
  ScheduleChecker checker(arms.world, arms.context);
  const std::uint64_t plain = arms.checksOver(checker, 0.0, 10.0);
  checker.alsoCheckAt(5.0);
  checker.alsoCheckAt(20.0);  // outside the interval checked: no effect
  EXPECT_GT(arms.checksOver(checker, 0.0, 10.0), plain);
  ScheduleChecker fresh(arms.world, arms.context);
  EXPECT_EQ(arms.checksOver(checker, 6.0, 10.0), arms.checksOver(fresh, 6.0, 10.0));  // 5 s is not in there
}

// Retiming checks the same standing robot against the same segments of the others again and again: the
// verdict over a whole segment is kept, so the same check again costs only the robot against the
// resting objects (its ends), and a longer standing over the same segment no more.
TEST(ScheduleChecker, AStandingRobotsVerdictOverASegmentIsReused) {
  TwoArms arms;
  ScheduleChecker checker(arms.world, arms.context);
  const std::uint64_t first = arms.checksOver(checker, 0.0, 10.0);
  const std::uint64_t again = arms.checksOver(checker, 0.0, 10.0);
  EXPECT_LT(again, first);
  EXPECT_EQ(arms.checksOver(checker, 2.0, 30.0), again);
  // The other arm now moves: a new segment, checked once.
  arms.timelines[1].append(12.0, arms.scene.robots[1].home);
  JointVector q = arms.scene.robots[1].home;
  q[0] += 0.3;
  arms.timelines[1].append(14.0, q);
  const std::uint64_t moving = arms.checksOver(checker, 0.0, 20.0);
  EXPECT_LT(arms.checksOver(checker, 0.0, 20.0), moving);
}

}  // namespace
}  // namespace dash
