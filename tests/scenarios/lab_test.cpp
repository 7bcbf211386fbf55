// Lab: the work needs both gantries (one grasps lids, the other inspects), every inspect pose is
// reachable once its lid is away, and the sanitisation zone holds only two lids at a time.
#include <gtest/gtest.h>

#include "engine/collision/collision_queries.h"
#include "engine/robots/kinematics.h"
#include "scenario_test_util.h"

namespace dash {
namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

TEST(Lab, EachContainerHasALidAndAnInspectTaskNeedingBothGantries) {
  for (const int containers : {1, 4, 8}) {
    const auto g = test::generate("lab", {{"containers", std::to_string(containers)}}, 3);
    const Scene& s = g.scene;
    ASSERT_EQ(s.robots.size(), 2u);
    EXPECT_EQ(s.robots[0].capabilities, std::vector<std::string>{"grasp"});
    EXPECT_EQ(s.robots[1].capabilities, std::vector<std::string>{"inspect"});
    ASSERT_EQ(static_cast<int>(s.tasks.size()), containers);
    ASSERT_EQ(static_cast<int>(s.objects.size()), 2 * containers);
    for (const SceneTask& t : s.tasks) {
      const SceneObject& container = s.objects[at(t.target_object)];
      const SceneObject& lid = s.objects[at(t.requires_removed_object)];
      EXPECT_TRUE(container.fixed);
      EXPECT_FALSE(lid.fixed);
      ASSERT_TRUE(lid.X_WO_goal.has_value());
      EXPECT_TRUE(lid.X_WO_goal->isApprox(lid.X_WO_start));
      EXPECT_EQ(t.capability, "inspect");
      // Over the container, and within gantry_1's reach (the only robot that can inspect).
      EXPECT_NEAR((t.X_WT.translation() - container.X_WO_start.translation()).head<2>().norm(), 0.0, 1e-9);
      EXPECT_EQ(inverseKinematics(*s.robots[1].model, s.robots[1].X_WB, t.X_WT).size(), 1u);
    }
  }
}

TEST(Lab, LidsStartAndEndWhereOnlyTheGraspingGantryTakesThem) {
  const auto g = test::generate("lab", {{"containers", "8"}}, 7);
  const Scene& s = g.scene;
  const CollisionWorld world(s);
  CollisionContext context(world);
  const ObjectLayout start = ObjectLayout::atStart(s);
  for (std::size_t j = 0; j < s.objects.size(); ++j) {
    if (s.objects[j].fixed) continue;
    EXPECT_EQ(robotsAbleToGrasp(world, context, static_cast<int>(j), s.objects[j].X_WO_start, start),
              std::vector<int>{0});
  }
}

TEST(Lab, SanitisationZoneHoldsTwoLids) {
  for (const std::uint64_t seed : {1ULL, 2ULL, 3ULL}) {
    const auto g = test::generate("lab", {}, seed);
    const SceneSurface* zone = nullptr;
    for (const auto& surface : g.scene.surfaces) {
      if (surface.id == "sanitisation_zone") zone = &surface;
    }
    ASSERT_NE(zone, nullptr);
    Eigen::AlignedBox2d box;
    for (const auto& p : zone->polygon) box.extend(p);
    const Vec3 lid = g.scene.objects[1].shape.size;
    const int along = static_cast<int>(box.sizes().x() / lid.x());
    const int across = static_cast<int>(box.sizes().y() / lid.y());
    EXPECT_EQ(along * across, 2);
    // Only gantry_0 reaches the zone.
    const auto& g1 = g.scene.robots[1];
    const Vec3 centre(box.center().x(), box.center().y(), zone->z + 0.01);
    EXPECT_TRUE(inverseKinematics(*g1.model, g1.X_WB, makePose(centre, Quat(0, 1, 0, 0))).empty());
    const auto& g0 = g.scene.robots[0];
    EXPECT_EQ(inverseKinematics(*g0.model, g0.X_WB, makePose(centre, Quat(0, 1, 0, 0))).size(), 1u);
  }
}

}  // namespace
}  // namespace dash
