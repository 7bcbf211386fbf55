// The scheduler's continuous-time check: time is cut at every breakpoint of the two timelines of each
// pair, and at the instants the plan validator pointed at (alsoCheckAt), so the robots at exactly those
// instants are checked; a standing robot's verdict over another's segment is kept.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/collision/segment_queries.h"
#include "engine/conflict/schedule_checker.h"
#include "tests/conflict/two_arms.h"

namespace dash {
namespace {

struct TwoArms : testing::TwoArms {
  ObjectTimeline objects{layout};
  std::vector<RobotTimeline> timelines{RobotTimeline(0, scene.robots[0].home), RobotTimeline(1, scene.robots[1].home)};

  std::uint64_t checksOver(ScheduleChecker& checker, double from, double until) {
    return checksAgainst(checker, from, until, timelines);
  }
  std::uint64_t checksAgainst(ScheduleChecker& checker, double from, double until,
                              const std::vector<RobotTimeline>& others) {
    const std::uint64_t before = context.counters().configuration_checks;
    EXPECT_FALSE(checker.check(timelines[0], from, until, others, objects).has_value());
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

/// Arm 1 reaching toward arm 0 (the first posture of a grid of base turns, shoulders and elbows) where
/// the arms' boxes meet but the arms are clear of each other: their pieces are not apart, they go to
/// the exact check.
JointVector towardTheOther(TwoArms& arms) {
  SegmentBoxes boxes(arms.world, arms.context);
  const RobotTimeline zero(0, arms.scene.robots[0].home);
  const auto box0 = boxes.pieceBox(zero, 0.0, 1.0);
  const ObjectLayout none = ObjectLayout::empty(arms.scene);
  for (int k = 0; k < 32 * 5 * 3; ++k) {
    JointVector q = arms.scene.robots[1].home;
    q[0] += 2.0 * M_PI * (k % 32) / 32.0;
    q[1] = -0.25 * M_PI * ((k / 32) % 5);
    q[2] = 0.25 * M_PI * (k / 160 - 1);
    const auto box1 = boxes.pieceBox(RobotTimeline(1, q), 0.0, 1.0);
    const RobotMotion still[2] = {{{0, zero.last(), {}}, zero.last()}, {{1, q, {}}, q}};
    if (box0->intersects(*box1) &&
        !motionsInCollision(arms.world, arms.context, still, none, nullptr, {CheckScope::kRobotsOnly}))
      return q;
  }
  ADD_FAILURE() << "no posture of arm 1 meets arm 0's box";
  return arms.scene.robots[1].home;
}

// Retiming checks the same standing robot against the same segments of the others again and again: the
// verdict over a whole segment is kept, so the same check again costs only the robot against the
// resting objects (its ends), and a longer standing over the same segment no more.
TEST(ScheduleChecker, AStandingRobotsVerdictOverASegmentIsReused) {
  TwoArms arms;
  arms.timelines[1] = RobotTimeline(1, towardTheOther(arms));
  ScheduleChecker checker(arms.world, arms.context);
  const std::uint64_t first = arms.checksOver(checker, 0.0, 10.0);
  const std::uint64_t again = arms.checksOver(checker, 0.0, 10.0);
  EXPECT_LT(again, first);
  EXPECT_EQ(arms.checksOver(checker, 2.0, 30.0), again);
  // The other arm now moves: a new segment, checked once.
  JointVector q = arms.timelines[1].last();
  arms.timelines[1].append(12.0, q);
  q[0] += 0.05;
  arms.timelines[1].append(14.0, q);
  const std::uint64_t moving = arms.checksOver(checker, 0.0, 20.0);
  EXPECT_LT(arms.checksOver(checker, 0.0, 20.0), moving);
}

// The pieces are indexed by time and swept volume (SegmentBoxes): arm 0 standing at home and arm 1
// turning its base away from it sweep boxes that never meet, so checking arm 0 against both arms costs
// exactly what checking it against the resting objects alone costs.
TEST(ScheduleChecker, PiecesWhoseSweptBoxesAreApartCostNoCheck) {
  TwoArms arms;
  JointVector q = arms.scene.robots[1].home;
  q[1] -= 0.3;  // the shoulder lifts the arm, away from the other
  arms.timelines[1].append(2.0, q);
  arms.timelines[1].append(4.0, arms.scene.robots[1].home);
  ScheduleChecker checker(arms.world, arms.context);
  ScheduleChecker alone(arms.world, arms.context);
  const std::vector<RobotTimeline> only_itself{arms.timelines[0]};
  const std::uint64_t objects_only = arms.checksAgainst(alone, 0.0, 10.0, only_itself);
  EXPECT_EQ(arms.checksOver(checker, 0.0, 10.0), objects_only);
  EXPECT_EQ(checker.piecesApart(), 3u);  // arm 1's two segments and its standing after them
  EXPECT_EQ(checker.piecesChecked(), 0u);
}

}  // namespace
}  // namespace dash
