// Round trips in a task plan (an object taken from its place and put back) are removed unless something
// done meanwhile needs the place free (a frontier constraint).
#include <gtest/gtest.h>

#include <algorithm>

#include "engine/task/plan_shortcut.h"
#include "engine/task/task_query.h"
#include "tests/task/toy_problem.h"

namespace dash {
namespace {

struct Toy {
  Scene scene;
  TaskSpace space;
  TaskHypergraph hg;
  // o0 stays with r0 (x 0.0 -> -0.1); o1 goes from r0 to r1 (x 0.1 -> 1.1) by a handover.
  Toy() : scene(test::lineScene(2, {{0.0, -0.1}, {0.1, 1.1}})), space(scene) {
    hg.build(space, test::lineReachability(scene));
  }
  VertexId at(int object, int location) const { return *hg.find(TaskElement::objectAt(object, location)); }
  TaskStep step(TaskArcType type, int robot, int object, int location = -1, int robot2 = -1) const {
    for (HyperarcId a : hg.graph().hyperarcs()) {
      const TaskArc& arc = hg.graph().property(a);
      if (arc.type == type && arc.robot == robot && arc.object == object && arc.robot2 == robot2 &&
          (location < 0 || arc.location == location))
        return {a, arc, {}};
    }
    ADD_FAILURE() << "no such hyperarc";
    return {};
  }
  /// o1 taken out and handed to r1 and back while r0 moves o0, then o1's real route.
  TaskPlan planWithRoundTrip() const {
    const int o1_start = space.startLocation(1);
    TaskPlan plan;
    plan.steps = {step(TaskArcType::kPick, 0, 1, o1_start),
                  step(TaskArcType::kHandover, 0, 1, -1, 1),
                  step(TaskArcType::kPick, 0, 0, space.startLocation(0)),
                  step(TaskArcType::kPlace, 0, 0, space.goalLocation(0)),
                  step(TaskArcType::kHandover, 1, 1, -1, 0),
                  step(TaskArcType::kPlace, 0, 1, o1_start),
                  step(TaskArcType::kPick, 0, 1, o1_start),
                  step(TaskArcType::kHandover, 0, 1, -1, 1),
                  step(TaskArcType::kPlace, 1, 1, space.goalLocation(1))};
    rebuildDependencies(plan);
    return plan;
  }
};

TEST(PlanShortcut, RoundTripNobodyNeedsIsRemoved) {
  const Toy toy;
  int removed = 0;
  const TaskPlan plan = removeRoundTrips(toy.planWithRoundTrip(), toy.hg, {}, &removed);
  EXPECT_EQ(removed, 4);
  ASSERT_EQ(plan.steps.size(), 5u);
  EXPECT_EQ(plan.steps[0].action.object, 0);  // r0 moves o0 first, then o1's route
  EXPECT_EQ(plan.steps[2].action.object, 1);
  EXPECT_EQ(plan.steps[2].action.type, TaskArcType::kPick);
  EXPECT_EQ(plan.steps[2].after, std::vector<int>{1});  // r0's hand is free after placing o0
  EXPECT_EQ(plan.steps[3].after, std::vector<int>{2});
}

TEST(PlanShortcut, RoundTripThatFreesAPlaceIsKept) {
  const Toy toy;
  // o0 may not be placed at its goal while o1 rests at its start: the trip is what makes room.
  TaskConstraintSet constraints;
  ASSERT_TRUE(constraints.add({TaskConstraint::Kind::kFrontier, toy.at(1, toy.space.startLocation(1)),
                               toy.at(0, toy.space.goalLocation(0))}));
  int removed = -1;
  const TaskPlan plan = removeRoundTrips(toy.planWithRoundTrip(), toy.hg, constraints, &removed);
  EXPECT_EQ(removed, 0);
  EXPECT_EQ(plan.steps.size(), 9u);
}

TEST(PlanShortcut, DependenciesAreTheLastStepsTouchingTheSameRobotsAndObject) {
  const Toy toy;
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, {}, {}, Deadline());
  ASSERT_TRUE(result.found());
  TaskPlan rebuilt = result.plan;
  rebuildDependencies(rebuilt);
  for (std::size_t k = 0; k < rebuilt.steps.size(); ++k) {
    std::vector<int> expected = result.plan.steps[k].after;
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(rebuilt.steps[k].after, expected) << "step " << k;
  }
}

}  // namespace
}  // namespace dash
