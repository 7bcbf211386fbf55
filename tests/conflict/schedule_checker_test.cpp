// The scheduler's continuous-time check: time is cut at every breakpoint of every timeline, and at the
// instants the plan validator pointed at (alsoCheckAt), so the robots at exactly those instants are
// checked.
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

}  // namespace
}  // namespace dash
