// A motion constraint's region p is respected by the motion query: the move of the constrained history
// (robot, task step) is planned around it, every configuration and every segment of its path out of the
// region, while the moves of other histories are left as they were. Regions are tested conservatively
// (engine/collision/region_queries.h): a box that contains a body meets a region box.
#include <gtest/gtest.h>

#include "engine/collision/region_queries.h"
#include "engine/events/memory_sink.h"
#include "engine/motion/motion_constraints.h"
#include "engine/motion/motion_layer.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/robots/kinematics.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/task/task_layer.h"
#include "tests/motion/first_task_plan.h"

namespace dash {
namespace {

using lazy::historyOf;
using lazy::MotionConstraint;
using lazy::MotionConstraintSet;

using testing::FirstTaskPlan;

bool pathEntersRegion(const CollisionWorld& world, CollisionContext& context, int robot, const HeldObject& held,
                      const std::vector<JointVector>& path, const std::vector<Aabb>& region) {
  for (std::size_t i = 0; i < path.size(); ++i) {
    if (robotEntersRegions(world, context, RobotState{robot, path[i], held}, region)) return true;
    if (i + 1 < path.size() && segmentEntersRegions(world, context, RobotState{robot, path[i], held}, path[i + 1], region))
      return true;
  }
  return false;
}

/// A 6 cm cube around the TCP at q.
Aabb boxAtTcp(const FirstTaskPlan& run, int robot, const JointVector& q) {
  const SceneRobot& r = run.scene.robots[robot];
  const Vec3 c = forwardKinematics(*r.model, r.X_WB, q).X_WT.translation();
  return Aabb(c - Vec3::Constant(0.03), c + Vec3::Constant(0.03));
}

/// A 6 cm cube around the TCP halfway along a straight transit: in its way, away from both ends.
std::optional<Aabb> boxInTheWay(const FirstTaskPlan& run, int robot, const StepVisit& visit) {
  if (visit.transit.size() != 2) return std::nullopt;
  const Aabb box = boxAtTcp(run, robot, 0.5 * (visit.transit.front() + visit.transit.back()));
  const std::vector<Aabb> region{box};
  CollisionContext context(run.world);
  for (const JointVector* q : {&visit.transit.front(), &visit.transit.back()})
    if (robotEntersRegions(run.world, context, RobotState{robot, *q, visit.held_before}, region)) return std::nullopt;
  return box;
}

TEST(MotionConstraintRegion, TheConstrainedHistorysMoveIsReplannedOutOfTheRegionAndOthersStay) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("sorting", {{"robots", "2"}, {"objects", "4"}});
  ASSERT_EQ(run.layer.status, TaskLayerStatus::kFeasible) << run.layer.reason;
  const MotionLayerResult before = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(before.status, MotionStatus::kOk) << before.reason;
  // The first straight transit long enough to have a box in its way, away from its ends.
  int robot = -1;
  std::size_t visit_index = 0;
  std::optional<Aabb> box;
  for (int r = 0; r < static_cast<int>(before.robots.size()) && !box; ++r)
    for (std::size_t i = 0; i < before.robots[r].visits.size() && !box; ++i)
      if ((box = boxInTheWay(run, r, before.robots[r].visits[i]))) {
        robot = r;
        visit_index = i;
      }
  ASSERT_TRUE(box.has_value()) << "no straight transit with room for a region";
  const StepVisit& old_visit = before.robots[robot].visits[visit_index];
  ASSERT_TRUE(pathEntersRegion(run.world, run.context, robot, old_visit.held_before, old_visit.transit, {*box}));

  MotionConstraintSet constraints;
  MotionConstraint c;
  c.histories = {historyOf(run.layer.plan, robot, old_visit.step)};
  c.region = {*box};
  constraints.add(c);
  EXPECT_EQ(constraints.regionsFor(run.layer.plan, robot, old_visit.step, old_visit.q).size(), 1u);
  EXPECT_TRUE(constraints.regionsFor(run.layer.plan, 1 - robot, old_visit.step, old_visit.q).empty());
  run.motion.respect(&constraints);
  const MotionLayerResult after = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(after.status, MotionStatus::kOk) << after.reason;
  const StepVisit& new_visit = after.robots[robot].visits[visit_index];
  ASSERT_EQ(new_visit.step, old_visit.step);
  EXPECT_GT(new_visit.transit.size(), 2u);  // around the region, not straight through it
  EXPECT_FALSE(pathEntersRegion(run.world, run.context, robot, new_visit.held_before, new_visit.transit, {*box}));
  EXPECT_EQ((new_visit.transit.front() - old_visit.transit.front()).norm(), 0.0);
  EXPECT_EQ((new_visit.transit.back() - old_visit.transit.back()).norm(), 0.0);
  // The other robot's moves are the same (its histories have no constraint).
  const int other = 1 - robot;
  ASSERT_EQ(after.robots[other].visits.size(), before.robots[other].visits.size());
  for (std::size_t i = 0; i < before.robots[other].visits.size(); ++i)
    EXPECT_EQ(after.robots[other].visits[i].transit.size(), before.robots[other].visits[i].transit.size());
}

TEST(MotionConstraintRegion, ARegionTheMovesStartOrApproachStartIsInCannotBeKeptOutOf) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("sorting", {{"robots", "2"}, {"objects", "4"}});
  ASSERT_EQ(run.layer.status, TaskLayerStatus::kFeasible) << run.layer.reason;
  const MotionLayerResult motions = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(motions.status, MotionStatus::kOk) << motions.reason;
  bool checked = false;
  for (int r = 0; r < static_cast<int>(motions.robots.size()) && !checked; ++r)
    for (const StepVisit& v : motions.robots[r].visits) {
      const std::optional<Aabb> in_the_way = boxInTheWay(run, r, v);
      if (!in_the_way) continue;
      EXPECT_FALSE(run.motion.fixedEndsEnter(motions, r, v.step, {*in_the_way}));
      EXPECT_TRUE(run.motion.fixedEndsEnter(motions, r, v.step, {boxAtTcp(run, r, v.q_pre)}));
      EXPECT_TRUE(run.motion.fixedEndsEnter(motions, r, v.step, {*in_the_way, boxAtTcp(run, r, v.transit.front())}));
      checked = true;
      break;
    }
  EXPECT_TRUE(checked) << "no straight transit with room for a region";
}

/// Three steps, hyperarcs 10, 11, 12: robot 0, robot 1, robot 0.
TaskPlan threeSteps() {
  TaskPlan plan;
  for (int k = 0; k < 3; ++k) {
    TaskStep s;
    s.arc = HyperarcId(static_cast<std::uint32_t>(10 + k));
    s.action.robot = k == 1 ? 1 : 0;
    plan.steps.push_back(s);
  }
  return plan;
}

TEST(MotionConstraintRegion, AHistoryIsMatchedByTheRobotsOwnTransitionsNotByTheStepNumber) {
  const TaskPlan plan = threeSteps();
  const MotionConstraint::History h = historyOf(plan, 0, 2);
  EXPECT_EQ(h.arcs, (std::vector<std::uint32_t>{10, 12}));
  MotionConstraintSet set;
  MotionConstraint c;
  c.histories = {h};
  c.region = {Aabb(Vec3::Zero(), Vec3::Ones())};
  set.add(c);
  const JointVector q = JointVector::Zero(6);
  EXPECT_EQ(set.regionsFor(plan, 0, 2, q).size(), 1u);
  EXPECT_TRUE(set.regionsFor(plan, 0, 0, q).empty());  // another history of the same robot
  // The same robot history in a plan where another robot's step comes first: still the same history.
  TaskPlan shifted;
  TaskStep first;
  first.arc = HyperarcId(99);
  first.action.robot = 1;
  shifted.steps = {first, plan.steps[0], plan.steps[2]};
  EXPECT_EQ(set.regionsFor(shifted, 0, 2, q).size(), 1u);
  // A constraint learned at one transition configuration is lifted when another one is drawn.
  MotionConstraint at_q = c;
  at_q.histories.front().q = JointVector::Constant(6, 0.5);
  MotionConstraintSet scoped;
  scoped.add(at_q);
  EXPECT_EQ(scoped.regionsFor(plan, 0, 2, JointVector::Constant(6, 0.5)).size(), 1u);
  EXPECT_TRUE(scoped.regionsFor(plan, 0, 2, q).empty());
  // A restart lifts them all.
  EXPECT_EQ(scoped.liftAll(), std::vector<std::size_t>{0});
  EXPECT_TRUE(scoped.regionsFor(plan, 0, 2, JointVector::Constant(6, 0.5)).empty());
  EXPECT_EQ(scoped.size(), 1u);  // kept for the record
}

TEST(MotionConstraintRegion, TheRegionsAMoveFoundNoWayAroundAreLiftedForThatHistoryAlone) {
  const TaskPlan plan = threeSteps();
  const JointVector q = JointVector::Zero(6);
  MotionConstraint first, second, other_robot;
  first.histories = {historyOf(plan, 0, 2)};
  first.region = {Aabb(Vec3::Zero(), Vec3::Ones())};
  second = first;
  second.region = {Aabb(Vec3::Ones(), 2 * Vec3::Ones())};
  other_robot.histories = {historyOf(plan, 1, 1)};
  other_robot.region = first.region;
  MotionConstraintSet set;
  set.add(first);
  set.add(other_robot);
  set.add(second);
  set.add(MotionConstraint{.histories = {historyOf(plan, 0, 0)}, .region = first.region});  // an earlier history
  EXPECT_EQ(set.regionsFor(plan, 0, 2, q).size(), 2u);
  EXPECT_EQ(set.liftRegionsFor(plan, 0, 2, q), (std::vector<std::size_t>{0, 2}));
  EXPECT_TRUE(set.regionsFor(plan, 0, 2, q).empty());
  EXPECT_FALSE(set.contains(first));  // learned again, it would be in force again
  EXPECT_FALSE(set.inForce(0));
  EXPECT_TRUE(set.inForce(1));
  EXPECT_EQ(set.regionsFor(plan, 1, 1, q).size(), 1u);
  EXPECT_EQ(set.regionsFor(plan, 0, 0, q).size(), 1u);
  EXPECT_TRUE(set.liftRegionsFor(plan, 0, 2, q).empty());  // nothing left to lift there
  EXPECT_EQ(set.liftAll(), (std::vector<std::size_t>{1, 3}));
  EXPECT_EQ(set.size(), 4u);  // kept for the record
}

}  // namespace
}  // namespace dash
