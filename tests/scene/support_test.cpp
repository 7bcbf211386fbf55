#include <gtest/gtest.h>

#include "engine/scene/scene_json.h"
#include "engine/scene/support.h"
#include "tests/scene/scene_test_util.h"

namespace dash {
namespace {

using Vec2 = Eigen::Vector2d;

Scene example() { return loadScene(test::exampleScenePath(), test::library()); }

Pose at(double x, double y, double z, double yaw = 0.0) {
  return makePose(Vec3(x, y, z), Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())));
}

TEST(Support, CubeOnTheTable) {
  const Scene scene = example();
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  const Support s = findSupport(scene, 0, scene.objects[0].X_WO_start, layout);
  EXPECT_EQ(s.kind, Support::Kind::kSurface);
  EXPECT_EQ(s.index, 0);
  EXPECT_TRUE(findSupport(scene, 0, *scene.objects[0].X_WO_goal, layout).found());
  EXPECT_TRUE(findSupport(scene, 0, at(0.3, 0.3, 0.02, 0.7), layout).found());    // any yaw
  EXPECT_TRUE(findSupport(scene, 0, at(0.3, 0.3, 0.0209), layout).found());       // within 1 mm
}

TEST(Support, FloatingSunkOrTiltedIsNotResting) {
  const Scene scene = example();
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  EXPECT_FALSE(findSupport(scene, 0, at(0.3, 0.3, 0.05), layout).found());
  EXPECT_FALSE(findSupport(scene, 0, at(0.3, 0.3, 0.018), layout).found());
  const Pose tilted = makePose(Vec3(0.3, 0.3, 0.02), Quat(Eigen::AngleAxisd(0.2, Vec3::UnitX())));
  EXPECT_FALSE(findSupport(scene, 0, tilted, layout).found());
  // Lying on another face is fine: a quarter turn about x.
  const Pose on_side = makePose(Vec3(0.3, 0.3, 0.02), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX())));
  EXPECT_TRUE(findSupport(scene, 0, on_side, layout).found());
}

TEST(Support, FootprintMustBeInsideThePolygon) {
  const Scene scene = example();
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  EXPECT_TRUE(findSupport(scene, 0, at(1.4805, 0.0, 0.02), layout).found());  // 0.5 mm overhang: inside tolerance
  EXPECT_FALSE(findSupport(scene, 0, at(1.49, 0.0, 0.02), layout).found());   // 1 cm overhang
  EXPECT_FALSE(findSupport(scene, 0, at(2.0, 0.0, 0.02), layout).found());
}

TEST(Support, NonConvexPolygonNotch) {
  // A U shape: the notch (x in [0.4, 0.6], y > 0.2) is not part of the surface.
  const std::vector<Vec2> u = {{0, 0}, {1, 0}, {1, 1}, {0.6, 1}, {0.6, 0.2}, {0.4, 0.2}, {0.4, 1}, {0, 1}};
  const std::array<Vec2, 4> inside = {Vec2(0.1, 0.1), Vec2(0.3, 0.1), Vec2(0.3, 0.3), Vec2(0.1, 0.3)};
  EXPECT_TRUE(footprintInsidePolygon(inside, u, 1e-3));
  // Corners all inside the U, but the notch cuts through the footprint.
  const std::array<Vec2, 4> straddle = {Vec2(0.3, 0.5), Vec2(0.7, 0.5), Vec2(0.7, 0.6), Vec2(0.3, 0.6)};
  EXPECT_FALSE(footprintInsidePolygon(straddle, u, 1e-3));
  // Clockwise polygons work too.
  std::vector<Vec2> reversed(u.rbegin(), u.rend());
  EXPECT_TRUE(footprintInsidePolygon(inside, reversed, 1e-3));
  EXPECT_FALSE(footprintInsidePolygon(straddle, reversed, 1e-3));
}

TEST(Support, StackedOnAnotherObject) {
  Scene scene = example();
  SceneObject top = scene.objects[0];
  top.id = "obj_1";
  top.X_WO_start = at(-0.5, -0.2, 0.06);
  top.X_WO_goal.reset();
  scene.objects.push_back(top);
  ObjectLayout layout = ObjectLayout::atStart(scene);
  const Support s = findSupport(scene, 1, layout.X_WO[1], layout);
  EXPECT_EQ(s.kind, Support::Kind::kObject);
  EXPECT_EQ(s.index, 0);
  // Overhanging the cube below by 1 cm is not supported; nor is anything when the cube below is gone.
  EXPECT_FALSE(findSupport(scene, 1, at(-0.49, -0.2, 0.06), layout).found());
  layout.remove(0);
  EXPECT_FALSE(findSupport(scene, 1, layout.X_WO[1], layout).found());
}

TEST(ObjectLayout, StartGoalEmpty) {
  const Scene scene = example();
  const ObjectLayout start = ObjectLayout::atStart(scene);
  const ObjectLayout goal = ObjectLayout::atGoal(scene);
  const ObjectLayout none = ObjectLayout::empty(scene);
  ASSERT_EQ(start.size(), 1);
  EXPECT_TRUE(start.isPresent(0));
  EXPECT_FALSE(none.isPresent(0));
  EXPECT_TRUE(start.X_WO[0].isApprox(scene.objects[0].X_WO_start));
  EXPECT_TRUE(goal.X_WO[0].isApprox(*scene.objects[0].X_WO_goal));
}

}  // namespace
}  // namespace dash
