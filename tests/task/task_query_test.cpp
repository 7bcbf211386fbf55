#include <gtest/gtest.h>

#include "engine/task/task_query.h"
#include "tests/task/toy_problem.h"

namespace dash {
namespace {

int countType(const TaskPlan& plan, TaskArcType t) {
  int n = 0;
  for (const auto& s : plan.steps) n += s.action.type == t ? 1 : 0;
  return n;
}

struct Toy {
  Scene scene;
  TaskSpace space;
  TaskHypergraph hg;
  explicit Toy(Scene s) : scene(std::move(s)), space(scene) { hg.build(space, test::lineReachability(scene)); }
  VertexId at(int object, int location) const { return *hg.find(TaskElement::objectAt(object, location)); }
  VertexId goal(int object) const { return at(object, space.goalLocation(object)); }
};

std::pair<int, int> goalPlacementSteps(const TaskPlan& plan, const TaskSpace& space) {
  int place0 = -1, place1 = -1;
  for (int i = 0; i < static_cast<int>(plan.steps.size()); ++i) {
    const auto& a = plan.steps[i].action;
    if (a.type == TaskArcType::kPlace && a.location == space.goalLocation(a.object))
      (a.object == 0 ? place0 : place1) = i;
  }
  return {place0, place1};
}

TEST(TaskHypergraph, TwoRobotsOneObjectOneHandover) {
  const Scene scene = test::lineScene(2, {{0.0, 1.0}});
  TaskSpace space(scene);
  const TaskReachability reach = test::lineReachability(scene);
  TaskHypergraph hg;
  int vertices = 0, arcs = 0;
  hg.build(space, reach, {[&](VertexId, const TaskElement&) { ++vertices; },
                          [&](HyperarcId, const TaskArc&) { ++arcs; }});
  EXPECT_EQ(static_cast<std::size_t>(vertices), hg.graph().vertexCount());
  EXPECT_EQ(static_cast<std::size_t>(arcs), hg.graph().hyperarcCount());
  // source, sink, r0, r1, o0@start, o0@goal, r0+o0 and r1+o0 with top and side grasps.
  EXPECT_EQ(hg.graph().vertexCount(), 10u);

  // Building again adds nothing: the closure is reached and ids stay stable.
  int again = 0;
  hg.build(space, reach, {[&](VertexId, const TaskElement&) { ++again; }, {}});
  EXPECT_EQ(again, 0);

  const TaskQueryResult result = queryTaskPlan(hg, space, {}, {}, Deadline());
  ASSERT_TRUE(result.found()) << toString(result.status);
  const TaskPlan& plan = result.plan;
  ASSERT_EQ(plan.steps.size(), 3u);
  EXPECT_EQ(countType(plan, TaskArcType::kPick), 1);
  EXPECT_EQ(countType(plan, TaskArcType::kHandover), 1);
  EXPECT_EQ(countType(plan, TaskArcType::kPlace), 1);
  EXPECT_EQ(plan.steps[0].action.robot, 0);
  EXPECT_EQ(plan.steps[2].action.robot, 1);
  EXPECT_EQ(plan.steps[1].after, std::vector<int>{0});
  EXPECT_EQ(plan.steps[2].after, std::vector<int>{1});
  EXPECT_NE(plan.describe(space).find("handover r0 -> r1 o0"), std::string::npos);
}

TEST(TaskQuery, IndependentObjectsRunInParallelThreads) {
  // o0 is r0's alone and o1 is r2's alone: the two threads share nothing.
  Toy toy(test::lineScene(3, {{0.1, -0.1}, {2.1, 1.9}}));
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, {}, {}, Deadline());
  ASSERT_TRUE(result.found());
  ASSERT_EQ(result.plan.steps.size(), 4u);
  for (const auto& s : result.plan.steps)
    for (int d : s.after) EXPECT_EQ(result.plan.steps[d].action.object, s.action.object);
}

TEST(TaskQuery, FrontierConstraintOrdersPlacements) {
  // o1 may not be placed at its goal while o0 rests at its goal: o1 must go first.
  Toy toy(test::lineScene(2, {{0.0, 1.0}, {0.1, 1.1}}));
  TaskConstraintSet constraints;
  ASSERT_TRUE(constraints.add({TaskConstraint::Kind::kFrontier, toy.goal(0), toy.goal(1)}));
  EXPECT_FALSE(constraints.add({TaskConstraint::Kind::kFrontier, toy.goal(0), toy.goal(1)}));
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, constraints, {}, Deadline());
  ASSERT_TRUE(result.found());
  const auto [place0, place1] = goalPlacementSteps(result.plan, toy.space);
  ASSERT_GE(place0, 0);
  ASSERT_GE(place1, 0);
  EXPECT_LT(place1, place0);
}

TEST(TaskQuery, HistoryConstraintOrdersPlacements) {
  // Once o1 has been at its goal, o0 may not be placed at its goal: o0 must go first.
  Toy toy(test::lineScene(2, {{0.0, 1.0}, {0.1, 1.1}}));
  TaskConstraintSet constraints;
  constraints.add({TaskConstraint::Kind::kHistory, toy.goal(1), toy.goal(0)});
  EXPECT_TRUE(constraints.historyRelevant(toy.goal(1)));
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, constraints, {}, Deadline());
  ASSERT_TRUE(result.found());
  const auto [place0, place1] = goalPlacementSteps(result.plan, toy.space);
  EXPECT_LT(place0, place1);
}

TEST(TaskQuery, ImpossibleProblemEndsExhausted) {
  // The goal is beyond every robot's reach: no place arc reaches it.
  Toy toy(test::lineScene(2, {{0.0, 5.0}}));
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, {}, {}, Deadline());
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
  EXPECT_EQ(result.unroutable_object, 0);  // said without a search
  EXPECT_EQ(result.stats.expansions, 0u);
}

TEST(TaskQuery, ContradictoryConstraintsEndExhaustedNotLooping) {
  // Each goal blocks the other: no order works without an extra location.
  Toy toy(test::lineScene(2, {{0.0, 1.0}, {0.1, 1.1}}));
  TaskConstraintSet constraints;
  constraints.add({TaskConstraint::Kind::kFrontier, toy.goal(0), toy.goal(1)});
  constraints.add({TaskConstraint::Kind::kFrontier, toy.goal(1), toy.goal(0)});
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, constraints, {}, Deadline());
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
  EXPECT_EQ(result.unroutable_object, -1);  // each object has its route; only the order is impossible
  EXPECT_GT(result.stats.expansions, 0u);
}

TEST(TaskQuery, InteractionConstraintsRemoveARoute) {
  Toy toy(test::lineScene(3, {{0.0, 2.0}}));
  ASSERT_TRUE(queryTaskPlan(toy.hg, toy.space, {}, {}, Deadline()).found());
  TaskConstraintSet constraints;
  for (GraspClass g1 : {GraspClass::kTop, GraspClass::kSide, GraspClass::kBottom})
    for (GraspClass g2 : {GraspClass::kTop, GraspClass::kSide, GraspClass::kBottom}) {
      TaskConstraint c;
      c.kind = TaskConstraint::Kind::kInteraction;
      c.giver = 0;
      c.receiver = 1;
      c.giver_grasp = g1;
      c.receiver_grasp = g2;
      constraints.add(c);
    }
  const TaskQueryResult result = queryTaskPlan(toy.hg, toy.space, constraints, {}, Deadline());
  EXPECT_EQ(result.status, HyperpathStatus::kExhausted);
  EXPECT_EQ(result.unroutable_object, 0);
  EXPECT_EQ(result.stats.expansions, 0u);
}

// Motion failures ban a hyperarc for a number of task queries, then the ban expires.
TEST(TaskConstraints, TemporaryBansExpireAfterTheirQueries) {
  TaskConstraintSet constraints;
  TaskConstraint once, thrice;
  once.kind = thrice.kind = TaskConstraint::Kind::kInteraction;
  once.temporary = thrice.temporary = true;
  once.arc = HyperarcId(1);
  thrice.arc = HyperarcId(2);
  thrice.queries = 3;
  constraints.add(once);
  constraints.add(thrice);
  EXPECT_EQ(constraints.expireTemporary().size(), 1u);  // `once` expires after one query
  EXPECT_EQ(constraints.size(), 1u);
  EXPECT_TRUE(constraints.expireTemporary().empty());
  const std::vector<TaskConstraint> last = constraints.expireTemporary();
  ASSERT_EQ(last.size(), 1u);
  EXPECT_EQ(last.front().arc, HyperarcId(2));
  EXPECT_TRUE(constraints.empty());
}

}  // namespace
}  // namespace dash
