// The narrow phase on the primitive pairs the checker uses, touching and apart.
#include <gtest/gtest.h>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>

#include "engine/collision/collision_internal.h"
#include "engine/collision/collision_queries.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

class ShapesTest : public ::testing::Test {
 protected:
  Scene scene = test::emptyScene();
  CollisionWorld world{scene};
  CollisionContext context{world};
};

TEST_F(ShapesTest, CapsuleAndBoxApartAndTouching) {
  const fcl::Capsuled capsule(0.05, 0.2);  // along z, centred on its frame
  const fcl::Boxd box(0.1, 0.1, 0.1);
  const Pose X_WC = Pose::Identity();
  for (const double gap : {0.01, 0.001}) {
    EXPECT_FALSE(detail::shapesCollide(context, capsule, X_WC, box, makePose(Vec3(0.05 + 0.05 + gap, 0, 0))))
        << "gap " << gap;
  }
  for (const double overlap : {0.001, 0.01}) {
    EXPECT_TRUE(detail::shapesCollide(context, capsule, X_WC, box, makePose(Vec3(0.1 - overlap, 0, 0))))
        << "overlap " << overlap;
  }
  // Beyond the capsule's end cap (z = 0.1 + 0.05): apart; just inside the cap: touching.
  EXPECT_FALSE(detail::shapesCollide(context, capsule, X_WC, box, makePose(Vec3(0, 0, 0.15 + 0.05 + 0.001))));
  EXPECT_TRUE(detail::shapesCollide(context, capsule, X_WC, box, makePose(Vec3(0, 0, 0.15 + 0.05 - 0.001))));
  // A rotated box whose edge reaches into the capsule's cylinder.
  const Pose X_WB = makePose(Vec3(0.05 + 0.05 * std::sqrt(2.0) - 0.002, 0, 0), Quat(Eigen::AngleAxisd(M_PI / 4, Vec3::UnitZ())));
  EXPECT_TRUE(detail::shapesCollide(context, capsule, X_WC, box, X_WB));
  EXPECT_EQ(context.counters().narrowphase_calls, 7u);
}

TEST_F(ShapesTest, CapsuleAndCapsule) {
  const fcl::Capsuled a(0.05, 0.2);
  const fcl::Capsuled b(0.04, 0.3);
  const Pose crossing = makePose(Vec3(0.0, 0.0, 0.0), Quat(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitX())));
  EXPECT_FALSE(detail::shapesCollide(context, a, Pose::Identity(), b, makePose(Vec3(0.091, 0, 0)) * crossing));
  EXPECT_TRUE(detail::shapesCollide(context, a, Pose::Identity(), b, makePose(Vec3(0.089, 0, 0)) * crossing));
}

TEST_F(ShapesTest, BoxAndBox) {
  const fcl::Boxd a(0.1, 0.1, 0.1);
  EXPECT_FALSE(detail::shapesCollide(context, a, Pose::Identity(), a, makePose(Vec3(0.101, 0, 0))));
  EXPECT_TRUE(detail::shapesCollide(context, a, Pose::Identity(), a, makePose(Vec3(0.099, 0.05, 0.05))));
}

}  // namespace
}  // namespace dash
