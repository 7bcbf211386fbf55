// Shelf-wall and Stocking: a rear slot can be reached only straight from the front and only while
// the slots in front of it are empty; objects cross the shelf's wall by handovers; stocking's existing
// items stay put and its staging posts take cubes from the side.
#include <gtest/gtest.h>

#include "engine/collision/collision_queries.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/collision/scene_check.h"
#include "engine/robots/kinematics.h"
#include "engine/scenarios/scenario_validation.h"
#include "scenario_test_util.h"

namespace dash {
namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

struct FreeGrasp {
  int robot;
  GraspCandidate grasp;
};

/// Every robot and grasp candidate that holds `object` at X_WO without a collision in `layout`.
std::vector<FreeGrasp> freeGrasps(const CollisionWorld& world, CollisionContext& context, int object, const Pose& X_WO,
                                  const ObjectLayout& layout) {
  std::vector<FreeGrasp> out;
  const Scene& scene = world.scene();
  for (int r = 0; r < world.robotCount(); ++r) {
    const SceneRobot& robot = scene.robots[at(r)];
    for (const auto& c : graspCandidates(*robot.model, robot.X_WB, scene.objects[at(object)].shape, X_WO)) {
      for (const JointVector& q : inverseKinematics(*robot.model, robot.X_WB, c.X_WT)) {
        if (!robotInCollision(world, context, {.robot = r, .q = q, .held = {.object = object, .X_TO = c.X_TO}},
                              layout)) {
          out.push_back({r, c});
          break;
        }
      }
    }
  }
  return out;
}

/// The blocked grasps of a generated shelf scene: impossible with the blockers in place, possible
/// without them, and then only horizontally, straight into the cubby. check-scene accepts them all:
/// the blockers are movable objects, which its grasp check never counts as in the way.
void checkBlockedGrasps(const GeneratedScenario& g) {
  const Scene& scene = g.scene;
  const CollisionWorld world(scene);
  CollisionContext context(world);
  ASSERT_FALSE(g.validation.blocked.empty());
  for (const SceneProblem& p : findSceneProblemsDetailed(scene)) ADD_FAILURE() << p.message;
  for (const BlockedGrasp& b : g.validation.blocked) {
    const SceneObject& o = scene.objects[at(b.object)];
    SCOPED_TRACE(o.id + (b.at_goal ? " at goal" : " at start"));
    const Pose& X = b.at_goal ? *o.X_WO_goal : o.X_WO_start;
    ObjectLayout layout = b.at_goal ? goalCheckLayout(scene) : ObjectLayout::atStart(scene);
    EXPECT_TRUE(freeGrasps(world, context, b.object, X, layout).empty());
    for (const int k : b.blockers) layout.remove(k);
    const auto free = freeGrasps(world, context, b.object, X, layout);
    ASSERT_FALSE(free.empty());
    // Straight in: every free grasp approaches horizontally, along the line to the blocker in front.
    const Vec3 front =
        (b.at_goal ? *scene.objects[at(b.blockers[0])].X_WO_goal : scene.objects[at(b.blockers[0])].X_WO_start)
            .translation();
    Vec3 inward = X.translation() - front;
    inward.z() = 0.0;  // pedestals rise towards the back; the way in is level
    inward.normalize();
    for (const auto& f : free) {
      const Vec3 z_T = f.grasp.X_WT.linear().col(2);
      EXPECT_GT(z_T.dot(inward), 0.999) << faceName(f.grasp.face);
    }
  }
}

TEST(ShelfWall, RearSlotsNeedTheFrontEmpty) {
  for (const auto& kv : std::vector<test::KeyValues>{{{"objects", "6"}}, {{"robots", "4"}, {"objects", "16"}}}) {
    checkBlockedGrasps(test::generate("shelf-wall", kv, 2));
  }
}

TEST(ShelfWall, ObjectsCrossTheWallByHandovers) {
  for (const int robots : {2, 4, 6}) {
    const auto g = test::generate("shelf-wall", {{"robots", std::to_string(robots)}, {"objects", "12"}}, 5);
    for (const auto& t : g.report.transfers) {
      for (const int r : t.start_robots) {
        EXPECT_EQ(std::find(t.goal_robots.begin(), t.goal_robots.end(), r), t.goal_robots.end());
      }
      EXPECT_GE(t.min_handovers, robots == 2 ? 1 : 2);
    }
    if (robots == 2) {
      for (const auto& t : g.report.transfers) EXPECT_EQ(t.min_handovers, 1);
    }
  }
}

TEST(Stocking, NewItemsGoBehindExistingOnes) {
  for (const int layers : {2, 3}) {
    const auto g = test::generate("stocking", {{"layers", std::to_string(layers)}, {"objects", "12"}}, 4);
    int fresh = 0;
    for (std::size_t j = 0; j < g.scene.objects.size(); ++j) {
      const SceneObject& o = g.scene.objects[j];
      ASSERT_TRUE(o.X_WO_goal.has_value());
      if (o.id.rfind("item_", 0) == 0) {
        EXPECT_TRUE(o.X_WO_goal->isApprox(o.X_WO_start)) << o.id;
      }
      if (o.id.rfind("new_", 0) == 0) ++fresh;
    }
    EXPECT_EQ(fresh, (12 + layers - 1) / layers);
    for (const auto& t : g.report.transfers) {
      const std::string& id = g.scene.objects[at(t.object)].id;
      EXPECT_EQ(t.min_handovers, id.rfind("new_", 0) == 0 ? 1 : 0) << id;
    }
    checkBlockedGrasps(g);
  }
}

TEST(Stocking, StagingPostsTakeCubesFromTheSideAndTheTop) {
  for (const int layers : {2, 3}) {
    const auto g = test::generate("stocking", {{"layers", std::to_string(layers)}}, 1);
    const Scene& scene = g.scene;
    const CollisionWorld world(scene);
    CollisionContext context(world);
    int posts = 0;
    for (const auto& s : scene.surfaces) {
      if (s.id.rfind("staging_", 0) != 0) continue;
      ++posts;
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (const auto& p : s.polygon) c += p;
      c /= static_cast<double>(s.polygon.size());
      const Pose X = makePose(Vec3(c.x(), c.y(), s.z + 0.02));
      bool side = false, top = false;
      for (const auto& f : freeGrasps(world, context, 0, X, ObjectLayout::empty(scene))) {
        if (f.robot != 0) continue;  // the stocker
        side |= f.grasp.face != GraspCandidate::Face::kTop && f.grasp.face != GraspCandidate::Face::kBottom;
        top |= f.grasp.face == GraspCandidate::Face::kTop;
      }
      EXPECT_TRUE(side) << s.id;
      EXPECT_TRUE(top) << s.id;
    }
    EXPECT_EQ(posts, layers);
  }
}

}  // namespace
}  // namespace dash
