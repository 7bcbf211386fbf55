// The scheduler's memo of the last schedule: the next build continues after the steps its plan shares
// with the last one, from exactly the state the schedule was in after them.
#include <gtest/gtest.h>

#include "engine/conflict/schedule_memo.h"

namespace dash {
namespace {

JointVector joints(double v) { return JointVector::Constant(6, v); }

TaskStep pick(int robot, int object, std::vector<int> after = {}) {
  TaskStep s;
  s.action.type = TaskArcType::kPick;
  s.action.robot = static_cast<std::int16_t>(robot);
  s.action.object = static_cast<std::int16_t>(object);
  s.after = std::move(after);
  return s;
}

TransitionConfig at(double v) {
  TransitionConfig c;
  c.sampled = true;
  c.q = joints(v);
  return c;
}

ObjectLayout twoObjects() { return ObjectLayout{{Pose::Identity(), Pose::Identity()}, {1, 1}}; }

struct Built {
  TaskPlan plan;
  std::vector<TransitionConfig> transitions;
  ScheduleMemo memo;
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {}};
};

// Two steps: robot 0 picks object 0 at t = 1, robot 1 picks object 1 at t = 2 (and robot 0 lets go).
Built buildTwoSteps() {
  Built b;
  b.plan.steps = {pick(0, 0), pick(1, 1, {0})};
  b.transitions = {at(0.1), at(0.2)};
  b.state.timelines = {RobotTimeline(0, joints(0.0)), RobotTimeline(1, joints(0.0))};
  b.state.step_time = {0.0, 0.0};
  b.memo.restart(0);
  b.state.timelines[0].append(1.0, joints(0.1));
  b.state.timelines[0].grasp(1.0, {0, Pose::Identity()});
  b.state.objects.pick(0, 1.0);
  b.state.events.push_back({PlanEvent::Type::kGrasp, 1.0, "r0", "o0", Pose::Identity(), -1});
  b.state.step_time[0] = 1.0;
  b.memo.recordStep(b.plan.steps[0], b.transitions[0], b.state);
  b.state.timelines[0].release(2.0);
  b.state.timelines[0].append(2.5, joints(0.0));
  b.state.timelines[1].append(2.0, joints(0.2));
  b.state.objects.pick(1, 2.0);
  b.state.step_time[1] = 2.0;
  b.memo.recordStep(b.plan.steps[1], b.transitions[1], b.state);
  b.memo.recordEnd(b.state);
  return b;
}

TEST(ScheduleMemo, NothingToResumeBeforeAnyBuild) {
  ScheduleMemo memo;
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {0.0}};
  TaskPlan plan;
  plan.steps = {pick(0, 0)};
  EXPECT_EQ(memo.resume(plan, {at(0.1)}, state), 0);
}

TEST(ScheduleMemo, TheSamePlanResumesAfterEveryStep) {
  Built b = buildTwoSteps();
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {0.0, 0.0, 0.0}};
  TaskPlan longer = b.plan;
  longer.steps.push_back(pick(0, 1, {1}));
  EXPECT_EQ(b.memo.resume(longer, {at(0.1), at(0.2), at(0.3)}, state), 2);
  EXPECT_EQ(state.timelines[0].points().size(), 3u);
  EXPECT_EQ(state.timelines[1].end(), 2.0);
  EXPECT_EQ(state.step_time, (std::vector<double>{1.0, 2.0, 0.0}));
}

TEST(ScheduleMemo, APlanThatPartsAtTheSecondStepGetsTheStateAfterTheFirst) {
  Built b = buildTwoSteps();
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {0.0, 0.0}};
  // The second step is the same action with another transition configuration.
  EXPECT_EQ(b.memo.resume(b.plan, {at(0.1), at(0.25)}, state), 1);
  ASSERT_EQ(state.timelines.size(), 2u);
  EXPECT_EQ(state.timelines[0].end(), 1.0);                    // robot 0's retreat after step 1 is gone
  EXPECT_EQ(state.timelines[0].heldAtEnd().object, 0);         // and it still holds object 0 (released later)
  EXPECT_EQ(state.timelines[1].points().size(), 1u);           // robot 1 has not moved yet
  EXPECT_TRUE(state.objects.layoutAt(5.0).isPresent(1));             // object 1 still rests
  EXPECT_FALSE(state.objects.layoutAt(5.0).isPresent(0));
  EXPECT_EQ(state.events.size(), 1u);
  EXPECT_EQ(state.step_time, (std::vector<double>{1.0, 0.0}));
}

TEST(ScheduleMemo, OtherDependenciesOrAnotherActionPartAtThatStep) {
  Built b = buildTwoSteps();
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {0.0, 0.0}};
  TaskPlan other = b.plan;
  other.steps[1].after.clear();
  EXPECT_EQ(b.memo.resume(other, b.transitions, state), 1);
  other = b.plan;
  other.steps[0].action.robot = 1;
  EXPECT_EQ(b.memo.resume(other, b.transitions, state), 0);
}

TEST(ScheduleMemo, RestartKeepsTheSharedStepsOnly) {
  Built b = buildTwoSteps();
  b.memo.restart(1);
  EXPECT_EQ(b.memo.steps(), 1);
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {0.0, 0.0}};
  EXPECT_EQ(b.memo.resume(b.plan, b.transitions, state), 1);
}

TEST(ScheduleMemo, ForgetsTheStepsWhoseMotionsReachATime) {
  Built b = buildTwoSteps();  // after step 1 robot 0 is at t = 1; after step 2 robot 0 reaches t = 2.5
  ScheduleState state{{}, ObjectTimeline(twoObjects()), {}, {0.0, 0.0}};
  b.memo.forgetFrom(2.2);
  EXPECT_EQ(b.memo.resume(b.plan, b.transitions, state), 1);
  b.memo.forgetFrom(1.0);
  EXPECT_EQ(b.memo.resume(b.plan, b.transitions, state), 0);
}

}  // namespace
}  // namespace dash
