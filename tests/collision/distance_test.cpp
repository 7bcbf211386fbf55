#include <gtest/gtest.h>

#include "engine/collision/distance_queries.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

TEST(Distance, RobotToObstaclesAndObjects) {
  Scene scene = test::emptyScene();
  test::addUr(scene, "ur", Pose::Identity());
  // A block whose face is 10 cm from the base capsule's side (radius 75 mm about the z axis).
  test::addObstacle(scene, "block", Vec3(0.1, 0.1, 0.05), makePose(Vec3(0.075 + 0.1 + 0.05, 0.0, 0.09)));
  test::addCube(scene, "cube", 0.04, makePose(Vec3(-0.3, 0.0, 0.02)));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  // Arm straight up: nothing but the base and the shoulder post is low.
  const JointVector up = test::joints({0, -M_PI / 2, 0, -M_PI / 2, 0, 0});
  DistanceReport report;
  const double d = robotDistance(world, context, {.robot = 0, .q = up}, ObjectLayout::empty(scene), &report);
  EXPECT_NEAR(d, 0.1, 1e-4);
  EXPECT_EQ(report.b, CollisionElement::obstacle(0));
  EXPECT_EQ(report.a.kind, CollisionElement::Kind::kRobotBody);
  EXPECT_EQ(scene.robots[0].model->bodies[static_cast<std::size_t>(report.a.body)].name, "base");
  // With the cube present the block is still the closest.
  const double d_cube = robotDistance(world, context, {.robot = 0, .q = up}, ObjectLayout::atStart(scene), &report);
  EXPECT_NEAR(d, d_cube, 1e-9);
  EXPECT_EQ(context.counters().distance_queries, 2u);
}

TEST(Distance, TwoRobots) {
  Scene scene = test::emptyScene();
  test::addUr(scene, "a", Pose::Identity());
  test::addUr(scene, "b", test::yawPose(0.5, 0.0, 0.0));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const JointVector up = test::joints({0, -M_PI / 2, 0, -M_PI / 2, 0, 0});
  DistanceReport report;
  const double d = robotsDistance(world, context, {.robot = 0, .q = up}, {.robot = 1, .q = up}, &report);
  EXPECT_GT(d, 0.0);
  EXPECT_LT(d, 0.5 - 2 * 0.075 + 1e-9);  // at most the gap between the two base capsules
  EXPECT_EQ(report.a.robot, 0);
  EXPECT_EQ(report.b.robot, 1);
  // Overlapping robots: zero.
  Scene overlap = test::emptyScene();
  test::addUr(overlap, "a", Pose::Identity());
  test::addUr(overlap, "b", test::yawPose(0.1, 0.0, 0.0));
  const CollisionWorld world2(overlap);
  CollisionContext context2(world2);
  EXPECT_EQ(robotsDistance(world2, context2, {.robot = 0, .q = up}, {.robot = 1, .q = up}), 0.0);
}

}  // namespace
}  // namespace dash
