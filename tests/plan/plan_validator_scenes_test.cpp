// The validator on hand-made scenes: two arms, a wall, a gantry with a lidded container, a handover.
#include <gtest/gtest.h>

#include <numbers>

#include "engine/plan/plan_validator.h"
#include "plan_test_util.h"

namespace dash {
namespace {

void expectKind(const ValidationReport& report, ProblemKind kind) {
  EXPECT_TRUE(report.has(kind)) << "expected " << problemKindName(kind) << ", got:\n" << report.summary();
}

TEST(TwoArms, ApartIsValid) {
  const Scene scene = test::twoArmScene();
  const ValidationReport report = validatePlan(scene, test::twoArmPlan(scene, -std::numbers::pi / 4.0));
  EXPECT_TRUE(report.valid()) << report.summary();
}

TEST(TwoArms, SwingingIntoTheOtherArmCollides) {
  const Scene scene = test::twoArmScene();
  const ValidationReport report = validatePlan(scene, test::twoArmPlan(scene, std::numbers::pi / 2.0));
  expectKind(report, ProblemKind::kRobotRobotCollision);
  for (const auto& p : report.problems) {
    EXPECT_EQ(p.kind, ProblemKind::kRobotRobotCollision) << report.summary();
    // A stretch of time, reported once per pair of bodies, not once per sample.
    EXPECT_LT(p.t, p.t_end);
    EXPECT_GT(p.t, 0.0);
    EXPECT_LT(p.t_end, 2.0);
    EXPECT_TRUE((p.robot == "ur5e_0" && p.other == "ur5e_1") || (p.robot == "ur5e_1" && p.other == "ur5e_0"));
  }
  EXPECT_LT(report.problems.size(), 40u);
}

TEST(TwoArms, ASingleThreadFindsTheSameProblems) {
  const Scene scene = test::twoArmScene();
  const Plan plan = test::twoArmPlan(scene, std::numbers::pi / 2.0);
  const ValidationReport many = validatePlan(scene, plan, {.threads = 4});
  const ValidationReport one = validatePlan(scene, plan, {.threads = 1});
  EXPECT_EQ(many.summary(), one.summary());
  EXPECT_EQ(many.samples, one.samples);
}

TEST(Wall, HeldCubeThroughAWallCollides) {
  Scene scene = test::exampleScene();
  const Plan plan = test::examplePlan();
  // The cube is carried at the height of point 5 along an arc about the base; the TCP stays at
  // constant height. A low wall across the arc's middle reaches 12 mm below the TCP: the fingers
  // (8 mm below it) pass over, the held cube (20 mm below) goes through.
  const RobotModel& model = *scene.robots[0].model;
  const Pose X_WT = forwardKinematics(model, scene.robots[0].X_WB, plan.robots[0].points[5].q).X_WT;
  const double radius = X_WT.translation().head<2>().norm();
  const double top = X_WT.translation().z() - 0.012;
  scene.obstacles.push_back({"wall", BoxShape{Vec3(0.2, 0.02, top)}, makePose(Vec3(-radius, 0.0, top / 2.0))});
  const ValidationReport report = validatePlan(scene, plan);
  expectKind(report, ProblemKind::kHeldObjectCollision);
  EXPECT_FALSE(report.has(ProblemKind::kRobotObstacleCollision)) << report.summary();
  for (const auto& p : report.problems) {
    if (p.kind != ProblemKind::kHeldObjectCollision) continue;
    EXPECT_EQ(p.object, "obj_0");
    EXPECT_EQ(p.other, "wall");
    EXPECT_GT(p.t, 1.69);
    EXPECT_LT(p.t_end, 2.18);
  }
}

TEST(Wall, ArmThroughAWallCollides) {
  Scene scene = test::exampleScene();
  // A tall wall across the same arc: now the arm hits it too.
  scene.obstacles.push_back({"wall", BoxShape{Vec3(0.2, 0.02, 1.0)}, makePose(Vec3(-0.54, 0.0, 0.5))});
  const ValidationReport report = validatePlan(scene, test::examplePlan());
  expectKind(report, ProblemKind::kRobotObstacleCollision);
}

TEST(Gantry, LidRemovedThenInspectIsValid) {
  const Scene scene = test::gantryScene();
  const ValidationReport report = validatePlan(scene, test::gantryPlan(scene, true));
  EXPECT_TRUE(report.valid()) << report.summary();
}

TEST(Gantry, InspectWithTheLidOnIsRejected) {
  const Scene scene = test::gantryScene();
  const ValidationReport report = validatePlan(scene, test::gantryPlan(scene, false));
  expectKind(report, ProblemKind::kInspectNotRemoved);
  EXPECT_EQ(report.problems.size(), 1u) << report.summary();
  EXPECT_EQ(report.problems[0].object, "container_0");  // the inspected object, though the event names none
  EXPECT_EQ(report.problems[0].other, "lid_0");
}

TEST(Gantry, InspectAwayFromThePoseIsRejected) {
  Scene scene = test::gantryScene();
  scene.tasks[0].X_WT.translation().z() += 0.01;
  expectKind(validatePlan(scene, test::gantryPlan(scene, true)), ProblemKind::kInspectPose);
}

TEST(Gantry, InspectWithoutTheCapabilityIsRejected) {
  Scene scene = test::gantryScene();
  scene.robots[0].capabilities = {"grasp"};
  expectKind(validatePlan(scene, test::gantryPlan(scene, true)), ProblemKind::kCapability);
}

TEST(Gantry, MissingInspectIsRejected) {
  const Scene scene = test::gantryScene();
  Plan plan = test::gantryPlan(scene, true);
  plan.events.pop_back();
  expectKind(validatePlan(scene, plan), ProblemKind::kTaskMissing);
}

TEST(Gantry, LidDroppedInMidAirIsRejected) {
  const Scene scene = test::gantryScene();
  Plan plan = test::gantryPlan(scene, true);
  plan.events[1].t -= 1.0;  // halfway down to the stand
  expectKind(validatePlan(scene, plan), ProblemKind::kReleaseUnstable);
}

/// Two gantries on the same rails over a stand with a 24 cm plank: each can hold one end of it.
Scene handoverScene() {
  const std::string text = R"({
    "format": "dashbench.scene/1", "name": "gantry-handover",
    "robots": [
      {"id": "gantry_0", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
       "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]},
      {"id": "gantry_1", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
       "home": [0.9, 0.1, 0.0], "capabilities": ["grasp"]}],
    "obstacles": [
      {"id": "stand", "shape": {"type": "box", "size": [0.3, 0.3, 0.11]}, "pose": {"p": [0.5, 0.3, 0.055], "q": [0, 0, 0, 1]}}],
    "surfaces": [{"id": "stand_top", "z": 0.11, "polygon": [[0.35, 0.15], [0.65, 0.15], [0.65, 0.45], [0.35, 0.45]]}],
    "objects": [{"id": "plank", "shape": {"type": "box", "size": [0.24, 0.06, 0.01]},
                 "start": {"p": [0.5, 0.3, 0.115], "q": [0, 0, 0, 1]}, "fixed": false}],
    "tasks": []
  })";
  return parseScene(text, test::library(), "gantry-handover");
}

/// gantry_0 lifts the plank by its left end, gantry_1 takes the right end, gantry_0 lets go, gantry_1
/// puts the plank down 10 cm further along y. With `sag`, gantry_0 sinks 5 cm while both hold it.
Plan handoverPlan(const Scene& scene, bool sag) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const auto& names = scene.robots[0].model->joint_names;
  const Quat down(0.0, 1.0, 0.0, 0.0);  // TCP frame: tool pointing down
  const Pose X_TO_left = makePose(Vec3(0.07, 0.0, 0.005), down);
  const Pose X_TO_right = makePose(Vec3(-0.07, 0.0, 0.005), down);
  using test::joints;
  using test::point;
  RobotTrajectory g0{"gantry_0", names, {point(0.0, scene.robots[0].home)}};
  g0.points.push_back(point(1.0, joints({0.43, 0.3, 0.0})));
  g0.points.push_back(point(3.0, joints({0.43, 0.3, 0.28})));
  plan.events.push_back({PlanEvent::Type::kGrasp, 3.0, "gantry_0", "plank", X_TO_left, -1});
  g0.points.push_back(point(5.0, joints({0.43, 0.3, 0.0})));
  g0.points.push_back(point(8.0, joints({0.43, 0.3, sag ? 0.05 : 0.0})));
  plan.events.push_back({PlanEvent::Type::kRelease, 8.0, "gantry_0", "plank", Pose::Identity(), -1});
  g0.points.push_back(point(9.0, scene.robots[0].home));
  RobotTrajectory g1{"gantry_1", names, {point(0.0, scene.robots[1].home)}};
  g1.points.push_back(point(6.0, joints({0.57, 0.3, 0.0})));
  g1.points.push_back(point(7.0, joints({0.57, 0.3, 0.0})));
  plan.events.push_back({PlanEvent::Type::kGrasp, 7.0, "gantry_1", "plank", X_TO_right, -1});
  g1.points.push_back(point(8.0, joints({0.57, 0.3, 0.0})));
  g1.points.push_back(point(9.0, joints({0.57, 0.4, 0.0})));
  g1.points.push_back(point(11.0, joints({0.57, 0.4, 0.28})));
  plan.events.push_back({PlanEvent::Type::kRelease, 11.0, "gantry_1", "plank", Pose::Identity(), -1});
  g1.points.push_back(point(13.0, joints({0.57, 0.4, 0.0})));
  g1.points.push_back(point(14.0, scene.robots[1].home));
  plan.robots = {g0, g1};
  plan.makespan = 14.0;
  return plan;
}

TEST(Handover, AgreeingAttachmentsAreValid) {
  const Scene scene = handoverScene();
  const ValidationReport report = validatePlan(scene, handoverPlan(scene, false));
  EXPECT_TRUE(report.valid()) << report.summary();
}

TEST(Handover, DisagreeingAttachmentsAreRejected) {
  const Scene scene = handoverScene();
  const ValidationReport report = validatePlan(scene, handoverPlan(scene, true));
  expectKind(report, ProblemKind::kHandover);
  EXPECT_EQ(report.count(ProblemKind::kHandover), 1) << report.summary();
}

TEST(Handover, ReleaseAndGraspAtTheSameInstantIsAHandover) {
  const Scene scene = handoverScene();
  Plan plan = handoverPlan(scene, false);
  plan.events[1].t = 7.0;  // gantry_0 lets go as gantry_1 grasps (listed before the grasp)
  plan.robots[0].points[4].t = 7.0;
  plan.robots[0].points[5].t = 8.0;
  plan.makespan = 14.0;
  const ValidationReport report = validatePlan(scene, plan);
  EXPECT_TRUE(report.valid()) << report.summary();
}

TEST(Handover, AThirdHandIsRejected) {
  const Scene scene = handoverScene();
  Plan plan = handoverPlan(scene, false);
  plan.events.push_back({PlanEvent::Type::kGrasp, 7.5, "gantry_1", "plank", plan.events[2].X_TO, -1});
  expectKind(validatePlan(scene, plan), ProblemKind::kGraspHeld);
}

}  // namespace
}  // namespace dash
