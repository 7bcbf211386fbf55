// Lab (paper, "Lab"): both gantries can lift lids and inspect every container, lids may rest only in
// the sanitisation zone (the one resting surface a lid fits on), and the zone has room for fewer lids
// than there are containers.
#include <gtest/gtest.h>

#include "engine/collision/collision_queries.h"
#include "engine/placement/placement_region.h"
#include "engine/robots/kinematics.h"
#include "scenario_test_util.h"

namespace dash {
namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

const SceneSurface& zoneOf(const Scene& s) {
  for (const auto& surface : s.surfaces)
    if (surface.id == "sanitisation_zone") return surface;
  throw std::runtime_error("no sanitisation_zone");
}

Eigen::AlignedBox2d boundsOf(const SceneSurface& surface) {
  Eigen::AlignedBox2d box;
  for (const auto& p : surface.polygon) box.extend(p);
  return box;
}

TEST(Lab, EachContainerHasALidAndAnInspectTaskBothGantriesCanDo) {
  for (const int containers : {2, 4, 16}) {
    const auto g = test::generate("lab", {{"containers", std::to_string(containers)}}, 3);
    const Scene& s = g.scene;
    ASSERT_EQ(s.robots.size(), 2u);
    for (const SceneRobot& r : s.robots) EXPECT_EQ(r.capabilities, (std::vector<std::string>{"grasp", "inspect"}));
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
      EXPECT_NEAR((t.X_WT.translation() - container.X_WO_start.translation()).head<2>().norm(), 0.0, 1e-9);
      for (const SceneRobot& r : s.robots) EXPECT_EQ(inverseKinematics(*r.model, r.X_WB, t.X_WT).size(), 1u) << r.id;
    }
  }
}

TEST(Lab, EitherGantryCanTakeEveryLid) {
  const auto g = test::generate("lab", {{"containers", "16"}}, 7);
  const Scene& s = g.scene;
  const CollisionWorld world(s);
  CollisionContext context(world);
  const ObjectLayout start = ObjectLayout::atStart(s);
  for (std::size_t j = 0; j < s.objects.size(); ++j) {
    if (s.objects[j].fixed) continue;
    EXPECT_EQ(robotsAbleToGrasp(world, context, static_cast<int>(j), s.objects[j].X_WO_start, start),
              (std::vector<int>{0, 1}))
        << s.objects[j].id;
  }
}

TEST(Lab, TheZoneHasRoomForFewerLidsThanContainersAndBothGantriesReachIt) {
  for (const int containers : {2, 3, 4, 8, 16, 24}) {
    for (const std::uint64_t seed : {1ULL, 2ULL, 3ULL}) {
      const auto g = test::generate("lab", {{"containers", std::to_string(containers)}}, seed);
      const SceneSurface& zone = zoneOf(g.scene);
      const Eigen::AlignedBox2d box = boundsOf(zone);
      const Vec3 lid = g.scene.objects[1].shape.size;
      const int along = static_cast<int>(box.sizes().x() / lid.x());
      const int across = static_cast<int>(box.sizes().y() / lid.y());
      EXPECT_EQ(along * across, labZoneLids(containers));
      EXPECT_LT(along * across, containers);
      EXPECT_GE(along * across, 1);
      // Both gantries reach every corner where a lid can lie in the zone.
      for (const double fx : {0.0, 1.0})
        for (const double fy : {0.0, 1.0}) {
          const Eigen::Vector2d c = box.min() + 0.5 * lid.head<2>() +
                                    Eigen::Vector2d(fx, fy).cwiseProduct(box.sizes() - lid.head<2>());
          const Pose X_WT = makePose(Vec3(c.x(), c.y(), zone.z + lid.z()), Quat(0, 1, 0, 0));
          for (const SceneRobot& r : g.scene.robots) EXPECT_EQ(inverseKinematics(*r.model, r.X_WB, X_WT).size(), 1u);
        }
    }
  }
}

// The planners sample placements on the scene's resting surfaces: the zone must be the only one a lid
// fits on (containers stand on pads a hair smaller than a lid).
TEST(Lab, TheZoneIsTheOnlySurfaceALidFitsOn) {
  const auto g = test::generate("lab", {{"containers", "16"}}, 5);
  const Vec3 lid = g.scene.objects[1].shape.size;
  const BoxShape lid_box{lid};
  Rng rng(11);
  int zones = 0;
  for (const SceneSurface& surface : g.scene.surfaces) {
    const PlacementRegion region(surface);
    const bool fits = region.sample(lid_box, rng, 2000).has_value();
    EXPECT_EQ(fits, surface.id == "sanitisation_zone") << surface.id;
    zones += surface.id == "sanitisation_zone";
  }
  EXPECT_EQ(zones, 1);
}

TEST(Lab, TheContainersAxisReachesTwentyFour) {
  const ScenarioFamily& lab = scenarioFamily("lab");
  ASSERT_EQ(lab.params.size(), 1u);
  EXPECT_EQ(lab.params[0].max, 24);
  const auto g = test::generate("lab", {{"containers", "24"}}, 2);
  EXPECT_EQ(g.scene.tasks.size(), 24u);
  EXPECT_TRUE(g.report.ok());
}

}  // namespace
}  // namespace dash
