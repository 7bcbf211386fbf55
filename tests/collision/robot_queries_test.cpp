#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "engine/collision/collision_queries.h"
#include "engine/collision/distance_queries.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/collision/segment_queries.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

using Kind = CollisionElement::Kind;

/// First IK solution that is collision-free for `state` (q filled in), or an empty vector.
JointVector freeIk(const CollisionWorld& world, CollisionContext& context, RobotState state, const Pose& X_WT,
                   const ObjectLayout& layout) {
  const SceneRobot& robot = world.scene().robots[static_cast<std::size_t>(state.robot)];
  for (const JointVector& q : inverseKinematics(*robot.model, robot.X_WB, X_WT)) {
    state.q = q;
    if (!robotInCollision(world, context, state, layout)) return q;
  }
  return {};
}

TEST(RobotQueries, ExampleHomeIsFree) {
  const Scene scene = test::exampleScene();
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  CollisionReport report;
  EXPECT_FALSE(robotInCollision(world, context, {.robot = 0, .q = scene.robots[0].home}, layout, &report))
      << describe(report, scene);
  EXPECT_FALSE(robotInCollision(world, context, {.robot = 0, .q = scene.robots[0].home}, ObjectLayout::atGoal(scene)));
  EXPECT_FALSE(layoutInCollision(world, context, layout));  // the cube rests on the table: touching is fine
  EXPECT_GE(context.counters().configuration_checks, 3u);
}

TEST(RobotQueries, ArmThroughTheTable) {
  const Scene scene = test::exampleScene();
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  // Shoulder lifted 1.2 rad below the horizontal: the elbow ends about 0.23 m under the table top.
  const JointVector q = test::joints({0.0, 1.2, 0.0, 0.0, 0.0, 0.0});
  ASSERT_LT(forwardKinematics(*scene.robots[0].model, scene.robots[0].X_WB, q).X_WT.translation().z(), -0.1);
  CollisionReport report;
  EXPECT_TRUE(robotInCollision(world, context, {.robot = 0, .q = q}, layout, &report));
  EXPECT_EQ(report.a.kind, Kind::kRobotBody);
  EXPECT_EQ(report.a.robot, 0);
  EXPECT_EQ(report.b, CollisionElement::obstacle(0));
  EXPECT_NE(describe(report, scene).find("obstacle table"), std::string::npos) << describe(report, scene);
  // The same configuration passes when only objects are considered, and fails on the static part.
  EXPECT_FALSE(robotInCollision(world, context, {.robot = 0, .q = q}, layout, nullptr, CheckScope::kObjectsOnly));
  EXPECT_TRUE(robotInCollision(world, context, {.robot = 0, .q = q}, layout, nullptr, CheckScope::kStaticOnly));
}

TEST(RobotQueries, SelfCollisionIsReportedAsSelfPair) {
  const Scene scene = test::exampleScene();
  const CollisionWorld world(scene);
  CollisionContext context(world);
  // Elbow folded fully back: the wrist comes down onto the shoulder.
  const JointVector q = test::joints({0.0, -1.5708, 3.1, 0.0, 0.0, 0.0});
  CollisionReport report;
  ASSERT_TRUE(robotInCollision(world, context, {.robot = 0, .q = q}, ObjectLayout::empty(scene), &report,
                               CheckScope::kStaticOnly));
  EXPECT_EQ(report.a.kind, Kind::kRobotBody);
  EXPECT_EQ(report.b.kind, Kind::kRobotBody);
  EXPECT_EQ(report.a.robot, 0);
  EXPECT_EQ(report.b.robot, 0);
}

TEST(RobotQueries, TwoArmsReachingIntoTheSameSpot) {
  Scene scene = test::emptyScene();
  test::addTable(scene);
  test::addUr(scene, "left", test::yawPose(0, 0, 0));
  test::addUr(scene, "right", test::yawPose(1.0, 0, 0, M_PI));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::empty(scene);
  const Pose X_WT = test::toolDown(Vec3(0.5, 0.0, 0.3));
  const JointVector q_left = freeIk(world, context, {.robot = 0}, X_WT, layout);
  const JointVector q_right = freeIk(world, context, {.robot = 1}, X_WT, layout);
  ASSERT_EQ(q_left.size(), 6);
  ASSERT_EQ(q_right.size(), 6);
  const std::array<RobotState, 2> both{RobotState{.robot = 0, .q = q_left}, RobotState{.robot = 1, .q = q_right}};
  CollisionReport report;
  EXPECT_TRUE(robotsInCollision(world, context, both, layout, &report));
  EXPECT_EQ(report.a.kind, Kind::kRobotBody);
  EXPECT_EQ(report.b.kind, Kind::kRobotBody);
  EXPECT_EQ(report.a.robot, 0);
  EXPECT_EQ(report.b.robot, 1);
  // Robot-robot pairs are layout-independent: part of the static scope, not of the objects scope.
  EXPECT_TRUE(robotsInCollision(world, context, both, layout, nullptr, CheckScope::kStaticOnly));
  EXPECT_FALSE(robotsInCollision(world, context, both, layout, nullptr, CheckScope::kObjectsOnly));
  // One arm at home while the other reaches: free.
  const std::array<RobotState, 2> one{RobotState{.robot = 0, .q = q_left}, RobotState{.robot = 1, .q = test::urHome()}};
  EXPECT_FALSE(robotsInCollision(world, context, one, layout, &report)) << describe(report, scene);
}

/// One UR5e at the origin on the table, a cube of `edge` held in a top grasp at (0.5, 0, 0.2).
struct HeldCubeSetup {
  Scene scene = test::emptyScene();
  std::unique_ptr<CollisionWorld> world;
  std::unique_ptr<CollisionContext> context;
  RobotState state;

  HeldCubeSetup(double edge, bool with_wall) {
    test::addTable(scene);
    test::addUr(scene, "ur", Pose::Identity());
    const Pose X_WO = makePose(Vec3(0.5, 0.0, 0.2));
    test::addCube(scene, "cube", edge, X_WO);
    // A wall low enough to miss the gripper, reaching into the cube's +x side (cube x in [0.48, 0.52]).
    if (with_wall) test::addObstacle(scene, "wall", Vec3(0.01, 0.3, 0.2), makePose(Vec3(0.51, 0.0, 0.1)));
    world = std::make_unique<CollisionWorld>(scene);
    context = std::make_unique<CollisionContext>(*world);
    // Top grasp, fingers closing along world x (built here: graspCandidates drops cubes too wide to fit).
    const Pose X_WT = test::toolDown(X_WO.translation());
    state = {.robot = 0, .held = {.object = 0, .X_TO = X_WT.inverse() * X_WO}};
    // An IK solution whose empty arm clears the table and itself.
    for (const JointVector& q : inverseKinematics(*scene.robots[0].model, scene.robots[0].X_WB, X_WT)) {
      const RobotState empty{.robot = 0, .q = q};
      if (!robotInCollision(*world, *context, empty, ObjectLayout::empty(scene), nullptr, CheckScope::kStaticOnly)) {
        state.q = q;
        break;
      }
    }
  }
};

TEST(RobotQueries, GripperAroundItsHeldCubeIsNoCollision) {
  HeldCubeSetup setup(0.04, false);
  ASSERT_EQ(setup.state.q.size(), 6);
  const ObjectLayout layout = ObjectLayout::atStart(setup.scene);  // lists the cube: ignored while held
  CollisionReport report;
  EXPECT_FALSE(robotInCollision(*setup.world, *setup.context, setup.state, layout, &report))
      << describe(report, setup.scene);
  // The open gripper also clears the 4 cm cube when it merely rests there (5 mm each side).
  RobotState empty = setup.state;
  empty.held = {};
  EXPECT_FALSE(robotInCollision(*setup.world, *setup.context, empty, layout, &report)) << describe(report, setup.scene);
}

TEST(RobotQueries, GripperBodiesNeverCountAgainstTheHeldObject) {
  // A 6 cm cube is wider than the 5 cm finger opening: the fingers sit inside it.
  HeldCubeSetup setup(0.06, false);
  ASSERT_EQ(setup.state.q.size(), 6);
  const ObjectLayout layout = ObjectLayout::atStart(setup.scene);
  EXPECT_FALSE(robotInCollision(*setup.world, *setup.context, setup.state, layout));
  // Not held, the same cube at the same place is hit by a finger.
  RobotState empty = setup.state;
  empty.held = {};
  CollisionReport report;
  ASSERT_TRUE(robotInCollision(*setup.world, *setup.context, empty, layout, &report));
  EXPECT_EQ(report.a.kind, Kind::kRobotBody);
  EXPECT_TRUE(setup.scene.robots[0].model->bodies[static_cast<std::size_t>(report.a.body)].is_gripper);
  EXPECT_EQ(report.b, CollisionElement::object(0));
}

/// A top grasp at a cube at (0.5, 0, 0.2) with a neighbour `gap` beyond the +x finger's outer face
/// (world x 0.536), planned with a 2 mm clearance.
struct NeighbourSetup {
  Scene scene = test::emptyScene();
  std::unique_ptr<CollisionWorld> world;
  std::unique_ptr<CollisionContext> context;
  RobotState state;

  NeighbourSetup(double target_edge, double gap) {
    test::addTable(scene);
    test::addUr(scene, "ur", Pose::Identity());
    test::addCube(scene, "target", target_edge, makePose(Vec3(0.5, 0.0, 0.2)));
    test::addCube(scene, "neighbour", 0.04, makePose(Vec3(0.536 + gap + 0.02, 0.0, 0.2)));
    world = std::make_unique<CollisionWorld>(scene, CollisionWorldOptions{.clearance = 0.002});
    context = std::make_unique<CollisionContext>(*world);
    state = {.robot = 0};
    state.q = freeIk(*world, *context, state, test::toolDown(Vec3(0.5, 0.0, 0.2)), ObjectLayout::empty(scene));
  }
};

TEST(RobotQueries, GripperTouchesOnlyTheObjectItGrasps) {
  // The fingers pass 0.25 mm from a 49.5 mm cube: the one nearest the TCP, so contact is meant.
  NeighbourSetup close_target(0.0495, 0.01);
  ASSERT_EQ(close_target.state.q.size(), 6);
  const ObjectLayout layout = ObjectLayout::atStart(close_target.scene);
  CollisionReport report;
  EXPECT_FALSE(robotInCollision(*close_target.world, *close_target.context, close_target.state, layout, &report))
      << describe(report, close_target.scene);
  // A neighbour 1 mm from a finger is not being grasped: it must keep the 2 mm clearance.
  NeighbourSetup near(0.04, 0.001);
  ASSERT_EQ(near.state.q.size(), 6);
  ASSERT_TRUE(robotInCollision(*near.world, *near.context, near.state, ObjectLayout::atStart(near.scene), &report));
  EXPECT_EQ(report.b, CollisionElement::object(1));
  EXPECT_TRUE(near.scene.robots[0].model->bodies[static_cast<std::size_t>(report.a.body)].is_gripper);
  // 3 mm away it keeps the clearance.
  NeighbourSetup far(0.04, 0.003);
  EXPECT_FALSE(robotInCollision(*far.world, *far.context, far.state, ObjectLayout::atStart(far.scene), &report))
      << describe(report, far.scene);
}

TEST(RobotQueries, AHandThatHoldsAnObjectGraspsNoRestingOne) {
  // The fingers 0.25 mm from the 49.5 mm target, as above, but the hand holds the neighbour (where it
  // rests, 1 cm beyond the target): the target is not being grasped and must keep the 2 mm clearance
  // (a place next to a resting object; the validator allows contact only with the object held).
  NeighbourSetup setup(0.0495, 0.01);
  ASSERT_EQ(setup.state.q.size(), 6);
  const Pose X_WT = test::toolDown(Vec3(0.5, 0.0, 0.2));
  RobotState holding = setup.state;
  holding.held = {.object = 1, .X_TO = X_WT.inverse() * setup.scene.objects[1].X_WO_start};
  CollisionReport report;
  ASSERT_TRUE(robotInCollision(*setup.world, *setup.context, holding, ObjectLayout::atStart(setup.scene), &report));
  EXPECT_EQ(report.b, CollisionElement::object(0));
  EXPECT_TRUE(setup.scene.robots[0].model->bodies[static_cast<std::size_t>(report.a.body)].is_gripper);
  // Empty-handed, the same configuration grasps the target: contact is meant.
  EXPECT_FALSE(robotInCollision(*setup.world, *setup.context, setup.state, ObjectLayout::atStart(setup.scene), &report))
      << describe(report, setup.scene);
}

/// The smallest signed distance between ur's gripper bodies and cube 0's contact box along q0 -> q1,
/// sampled every 1/4000 of the segment (brute force, for comparison).
double sampledGripperDistance(const CollisionWorld& world, CollisionContext& context, const JointVector& q0,
                              const JointVector& q1) {
  const RobotGeometry& rg = world.robot(0);
  std::vector<Pose> frames(rg.bodies.size());
  double best = 1e9;
  for (int i = 0; i <= 4000; ++i) {
    bodyFrames(*rg.model, rg.robot->X_WB, q0 + (i / 4000.0) * (q1 - q0), frames);
    for (std::size_t b = 0; b < rg.bodies.size(); ++b)
      if (rg.bodies[b].is_gripper)
        best = std::min(best, signedDistance(context, *rg.bodies[b].shape, frames[b] * rg.bodies[b].X_FG,
                                             *world.object(0).contact_shape, world.scene().objects[0].X_WO_start));
  }
  return best;
}

// A gripper sweeping sideways past a 4 cm cube along a joint-space line between two TCP poses whose +x
// finger's inner face is `into` metres inside the cube's contact box (negative: outside), both ends
// well clear of it. The line bulges about a millimetre off the straight sweep, so `into` is 2 mm; the
// brute-force sampled distance says which side it passes on, and the advancement must agree.
TEST(RobotQueries, AGripperEnteringTheContactBoxBetweenClearEndsIsFound) {
  for (const double into : {0.002, -0.002}) {
    Scene scene = test::emptyScene();
    test::addUr(scene, "ur", Pose::Identity());
    test::addCube(scene, "target", 0.04, makePose(Vec3(0.5, 0.0, 0.2)));
    const CollisionWorld world(scene);
    CollisionContext context(world);
    const ObjectLayout layout = ObjectLayout::atStart(scene);
    const Pose X_WT = test::toolDown(Vec3(0.5, 0.0, 0.2));
    // Finger inner faces 25 mm either side of the TCP along its x axis; the contact box's faces 19 mm.
    const Vec3 x = X_WT.linear().col(0), y = X_WT.linear().col(1);
    const Vec3 shift = -(0.025 - 0.019 + into) * x;
    const JointVector q0 = freeIk(world, context, {.robot = 0}, makePose(shift - 0.045 * y) * X_WT, layout);
    ASSERT_EQ(q0.size(), 6);
    JointVector q1;
    const SceneRobot& ur = scene.robots[0];
    for (const JointVector& q : inverseKinematics(*ur.model, ur.X_WB, makePose(shift + 0.045 * y) * X_WT))
      if (q1.size() == 0 || (q - q0).cwiseAbs().maxCoeff() < (q1 - q0).cwiseAbs().maxCoeff()) q1 = q;
    ASSERT_EQ(q1.size(), 6);
    ASSERT_FALSE(robotInCollision(world, context, {.robot = 0, .q = q1}, layout));
    const double sampled = sampledGripperDistance(world, context, q0, q1);
    ASSERT_GT(std::abs(sampled), 0.0002) << "the sweep must pass clearly in or out, into " << into;
    ASSERT_EQ(sampled < 0.0, into > 0.0) << "sampled distance " << sampled << ", into " << into;
    EXPECT_EQ(gripperEntersContactBox(world, context, 0, q0, q1, layout), sampled < 0.0)
        << "sampled distance " << sampled << ", into " << into;
    EXPECT_EQ(gripperEntersContactBox(world, context, 0, q1, q0, layout), sampled < 0.0) << "reversed, into " << into;
  }
}

TEST(RobotQueries, HeldCubeAgainstAWall) {
  HeldCubeSetup setup(0.04, true);
  ASSERT_EQ(setup.state.q.size(), 6);
  const ObjectLayout layout = ObjectLayout::atStart(setup.scene);
  CollisionReport report;
  ASSERT_TRUE(robotInCollision(*setup.world, *setup.context, setup.state, layout, &report));
  EXPECT_EQ(report.a, CollisionElement::heldObject(0, 0));
  EXPECT_EQ(report.b, CollisionElement::obstacle(1));
  EXPECT_NE(describe(report, setup.scene).find("(held by ur)"), std::string::npos);
  // The held object moves with the robot: it belongs to the static part.
  EXPECT_TRUE(robotInCollision(*setup.world, *setup.context, setup.state, layout, nullptr, CheckScope::kStaticOnly));
  // With an empty hand the arm itself clears the wall.
  RobotState empty = setup.state;
  empty.held = {};
  EXPECT_FALSE(robotInCollision(*setup.world, *setup.context, empty, ObjectLayout::empty(setup.scene), &report))
      << describe(report, setup.scene);
}

TEST(RobotQueries, HeldCubeAgainstOtherObjectsAndTheOtherRobot) {
  Scene scene = test::emptyScene();
  test::addTable(scene);
  test::addUr(scene, "left", test::yawPose(0, 0, 0));
  test::addUr(scene, "right", test::yawPose(1.2, 0, 0, M_PI));
  test::addCube(scene, "held", 0.04, makePose(Vec3(0.5, 0.0, 0.3)));
  test::addCube(scene, "resting", 0.04, makePose(Vec3(0.5, 0.03, 0.3)));  // overlaps the held one
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const Pose X_WT = test::toolDown(Vec3(0.5, 0.0, 0.3));
  const Pose X_TO = X_WT.inverse() * scene.objects[0].X_WO_start;
  ObjectLayout layout = ObjectLayout::empty(scene);
  const JointVector q = freeIk(world, context, {.robot = 0}, X_WT, layout);
  ASSERT_EQ(q.size(), 6);
  layout.place(1, scene.objects[1].X_WO_start);
  CollisionReport report;
  const RobotState holding{.robot = 0, .q = q, .held = {.object = 0, .X_TO = X_TO}};
  ASSERT_TRUE(robotInCollision(world, context, holding, layout, &report));
  EXPECT_EQ(report.a, CollisionElement::heldObject(0, 0));
  EXPECT_EQ(report.b, CollisionElement::object(1));
  EXPECT_FALSE(robotInCollision(world, context, holding, layout, nullptr, CheckScope::kStaticOnly));
  // A held object (attached 0.7 m from the TCP) that reaches into the other robot's shoulder post.
  const Pose X_WO_far = makePose(Vec3(1.2, 0.0, 0.13));
  const RobotState reaching{.robot = 0, .q = q, .held = {.object = 0, .X_TO = X_WT.inverse() * X_WO_far}};
  const std::array<RobotState, 2> both{reaching, RobotState{.robot = 1, .q = test::urHome()}};
  ASSERT_TRUE(robotsInCollision(world, context, both, ObjectLayout::empty(scene), &report));
  EXPECT_EQ(report.a, CollisionElement::heldObject(0, 0));
  EXPECT_EQ(report.b.kind, Kind::kRobotBody);
  EXPECT_EQ(report.b.robot, 1);
  EXPECT_FALSE(robotInCollision(world, context, reaching, ObjectLayout::empty(scene)));  // alone: free
}

TEST(RobotQueries, GantryToolTouchesTheLidItGrasps) {
  Scene scene = test::emptyScene();
  test::addTable(scene);
  SceneRobot gantry;
  gantry.id = "gantry";
  gantry.model_name = "gantry3";
  gantry.model = scene.library->find("gantry3");
  gantry.home = test::joints({0.0, 0.0, 0.0});
  gantry.capabilities = {"grasp"};
  scene.robots.push_back(gantry);
  scene.objects.push_back({.id = "container", .shape = BoxShape{Vec3(0.1, 0.1, 0.12)}, .X_WO_start = makePose(Vec3(0.5, 0.3, 0.06)), .fixed = true});
  scene.objects.push_back({.id = "lid", .shape = BoxShape{Vec3(0.1, 0.1, 0.01)}, .X_WO_start = makePose(Vec3(0.5, 0.3, 0.125))});
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  const auto candidates = graspCandidates(*gantry.model, gantry.X_WB, scene.objects[1].shape, scene.objects[1].X_WO_start);
  ASSERT_EQ(candidates.size(), 1u);
  const auto q = inverseKinematics(*gantry.model, gantry.X_WB, candidates[0].X_WT);
  ASSERT_EQ(q.size(), 1u);
  CollisionReport report;
  // The tool's bottom face is the TCP: it touches the lid's top face, which is contact, not overlap.
  EXPECT_FALSE(robotInCollision(world, context, {.robot = 0, .q = q[0]}, layout, &report)) << describe(report, scene);
  const RobotState holding{.robot = 0, .q = q[0], .held = {.object = 1, .X_TO = candidates[0].X_TO}};
  EXPECT_FALSE(robotInCollision(world, context, holding, layout, &report)) << describe(report, scene);
  // 5 mm lower the tool is inside the resting lid, or the held lid inside the container.
  const JointVector lower = q[0] + test::joints({0.0, 0.0, 0.005});
  EXPECT_TRUE(robotInCollision(world, context, {.robot = 0, .q = lower}, layout, &report));
  EXPECT_EQ(report.b, CollisionElement::object(1));
  EXPECT_TRUE(robotInCollision(world, context, {.robot = 0, .q = lower, .held = holding.held}, layout, &report));
  EXPECT_EQ(report.a, CollisionElement::heldObject(0, 1));
  EXPECT_EQ(report.b, CollisionElement::object(0));
  // Lifting the lid straight up is free; a prismatic step moves every point by exactly |dq|.
  const JointVector lifted = test::joints({q[0][0], q[0][1], 0.0});
  EXPECT_FALSE(segmentInCollision(world, context, holding, lifted, layout, &report)) << describe(report, scene);
  EXPECT_NEAR(segmentSteps(world, 0, q[0], lifted, holding.held), q[0][2] / kSegmentResolution, 1.0);
}

TEST(RobotQueries, ObjectPlacement) {
  Scene scene = test::exampleScene();
  test::addCube(scene, "second", 0.04, makePose(Vec3(-0.5, -0.2, 0.06)));  // stacked on obj_0
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  EXPECT_FALSE(layoutInCollision(world, context, layout));  // stacked and resting: touching only
  CollisionReport report;
  EXPECT_TRUE(objectInCollision(world, context, 1, makePose(Vec3(-0.5, -0.19, 0.02)), layout, &report));
  EXPECT_EQ(report.a, CollisionElement::object(1));
  EXPECT_EQ(report.b, CollisionElement::object(0));
  EXPECT_TRUE(objectInCollision(world, context, 1, makePose(Vec3(0.5, 0.5, 0.015)), layout, &report));  // 5 mm into the table
  EXPECT_EQ(report.b, CollisionElement::obstacle(0));
  EXPECT_FALSE(objectInCollision(world, context, 1, makePose(Vec3(0.5, 0.5, 0.0195)), layout));  // 0.5 mm: tolerated
}

}  // namespace
}  // namespace dash
