// DaSH's approaches and retreats (transition_catalog.h) on a stocking scene with 3 layers: the held
// item comes down onto its pedestal (and lifts off it) on a straight TCP line that rises when it runs
// sideways, so it touches the pedestal only where it is put down (issue 36, item 9). Before, a grasp
// sample's approach was one joint-space segment q_hold -> q along the approach axis: it
// swung the TCP 1.4 to 17 cm off the straight line between its ends (this scene's 14 side grasps with
// a back-off) and, where it stayed near the line, slid the item along the pedestal's top with no rise.
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <string>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/collision/distance_queries.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/dash/transition_catalog.h"
#include "engine/robots/cartesian_path.h"
#include "engine/robots/kinematics.h"
#include "engine/task/geometric_reachability.h"
#include "tests/dash/dash_built.h"

namespace dash {
namespace {

using Catalog = test::Built;  // the scene up to DaSH's transition catalog (dash_built.h)

/// Along `path` (robot g.robot holding g.held), every 1/20 of each segment (a Cartesian path's
/// segments are a few mm long): the smallest signed distance between the held object's exact box and
/// any obstacle, over all samples (`all`) and over those whose TCP is more than 1 mm from where the
/// path starts (`away`: on the way, not at the placement).
/// Also the farthest the TCP strays from the straight line between the path's ends beyond the growth
/// backOffLine allows at its distance from the placement (`off_line`).
struct Clearances {
  double all = std::numeric_limits<double>::infinity();
  double away = std::numeric_limits<double>::infinity();
  double off_line = 0.0;
};

Clearances clearances(Catalog& c, const GraspSample& g, const std::vector<JointVector>& path) {
  const SceneRobot& r = c.scene.robots[g.robot];
  const ObjectGeometry& object = c.world.object(g.object);
  const Vec3 placement = forwardKinematics(*r.model, r.X_WB, path.front()).X_WT.translation();
  const Vec3 axis = (forwardKinematics(*r.model, r.X_WB, path.back()).X_WT.translation() - placement).normalized();
  Clearances out;
  for (std::size_t i = 0; i < path.size(); ++i)
    for (int k = 0; k <= (i == 0 ? 0 : 19); ++k) {
      const JointVector q = i == 0 ? path[0] : path[i - 1] + (k + 1) / 20.0 * (path[i] - path[i - 1]);
      const Pose X_WT = forwardKinematics(*r.model, r.X_WB, q).X_WT;
      double d = std::numeric_limits<double>::infinity();
      for (const ObstacleGeometry& o : c.world.obstacles())
        d = std::min(d, signedDistance(c.context, *object.shape, X_WT * g.held.X_TO, *o.shape, o.X_WO));
      out.all = std::min(out.all, d);
      const Vec3 p = X_WT.translation() - placement;
      if (p.norm() > 1e-3) out.away = std::min(out.away, d);
      // Off the line by more than backOffLine allows there (it allows more farther out).
      if (path.size() > 1)
        out.off_line = std::max(out.off_line, (p - p.dot(axis) * axis).norm() - kBackOffGrowth * p.norm());
    }
  return out;
}

TEST(DashApproach, SideGraspsIntoCubbiesPutTheHeldItemDownOnItsPedestalWithoutSlidingAlongIt) {
  Catalog c(test::dashScene("stocking", {{"layers", "3"}, {"objects", "18"}}));
  int side = 0;
  for (const GraspSample& g : c.catalog.grasps) {
    if (g.grasp != GraspClass::kSide || g.hold_path.size() < 2) continue;
    ++side;
    ASSERT_EQ(g.hold_path.front(), g.q);
    ASSERT_EQ(g.hold_path.back(), g.q_hold);
    const std::string what = c.scene.objects[g.object].id + " by " + c.scene.robots[g.robot].id;
    // At the placement it rests on the pedestal; it never goes 0.1 mm into anything, and it touches
    // nothing on the way (an approach that slides it along the pedestal's top scrapes it).
    EXPECT_LT(clearances(c, g, {g.q}).all, kHeldBottomTolerance) << what;
    const Clearances along = clearances(c, g, g.hold_path);
    EXPECT_GT(along.all, -kHeldBottomTolerance) << what;
    EXPECT_GT(along.away, 1e-6) << what;
    EXPECT_LT(along.off_line, 5e-5) << what;  // on the TCP's straight line (backOffLine: 0.02 mm + growth)
  }
  EXPECT_GT(side, 0);
}

}  // namespace
}  // namespace dash
