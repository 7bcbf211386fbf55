#include <gtest/gtest.h>

#include "engine/collision/grasp_candidates.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

TEST(GraspCandidates, UrGetsSixFacesTwoRotationsForASmallCube) {
  const RobotModel& ur = *test::library()->find("ur5e");
  EXPECT_NEAR(gripperOpening(ur), 0.05, 1e-12);
  const Pose X_WO = test::yawPose(0.4, 0.2, 0.02, 0.3);
  const auto candidates = graspCandidates(ur, Pose::Identity(), BoxShape{Vec3::Constant(0.04)}, X_WO);
  ASSERT_EQ(candidates.size(), 12u);
  for (const GraspCandidate& c : candidates) {
    // The held object's pose is TCP * X_TO (formats.md), and the TCP sits at the box centre.
    EXPECT_TRUE((c.X_WT * c.X_TO).isApprox(X_WO, 1e-12));
    EXPECT_LT((c.X_WT.translation() - X_WO.translation()).norm(), 1e-12);
    EXPECT_TRUE(c.X_WT.linear().isUnitary(1e-12));
    EXPECT_NEAR(c.X_WT.linear().determinant(), 1.0, 1e-12);
  }
  // The top grasp approaches downwards.
  EXPECT_EQ(candidates[0].face, GraspCandidate::Face::kTop);
  EXPECT_NEAR(candidates[0].X_WT.linear().col(2).z(), -1.0, 1e-12);
}

TEST(GraspCandidates, BoxesWiderThanTheOpeningAreOnlyGraspedAcrossTheirNarrowSide) {
  const RobotModel& ur = *test::library()->find("ur5e");
  // 4 x 8 x 4 cm: the fingers can only close across x or z: one rotation on the +-x and +-z faces,
  // two on the +-y faces.
  const auto candidates = graspCandidates(ur, Pose::Identity(), BoxShape{Vec3(0.04, 0.08, 0.04)}, Pose::Identity());
  EXPECT_EQ(candidates.size(), 8u);
  for (const GraspCandidate& c : candidates) {
    // The closing axis (TCP x) in the object frame never runs along the 8 cm edge.
    const Vec3 x_T_in_O = c.X_TO.inverse().linear().col(0);
    EXPECT_LT(std::abs(x_T_in_O.y()), 1e-12);
  }
  EXPECT_TRUE(graspCandidates(ur, Pose::Identity(), BoxShape{Vec3::Constant(0.08)}, Pose::Identity()).empty());
}

TEST(GraspCandidates, GantryOnlyTopToolDown) {
  const RobotModel& gantry = *test::library()->find("gantry3");
  const Pose X_WB = test::yawPose(0.1, 0.2, 0.0);
  const BoxShape lid{Vec3(0.1, 0.1, 0.01)};
  // Lids sit on containers: the tool reaches down to 0.1 m above the gantry's base.
  const Pose X_WO = makePose(Vec3(0.5, 0.4, 0.15));
  const auto candidates = graspCandidates(gantry, X_WB, lid, X_WO);
  ASSERT_EQ(candidates.size(), 1u);
  const GraspCandidate& c = candidates[0];
  EXPECT_EQ(c.face, GraspCandidate::Face::kTop);
  EXPECT_TRUE(c.X_WT.translation().isApprox(Vec3(0.5, 0.4, 0.155), 1e-12));  // top face centre
  EXPECT_NEAR(c.X_WT.linear().col(2).z(), -1.0, 1e-12);                       // tool down
  EXPECT_TRUE((c.X_WT * c.X_TO).isApprox(X_WO, 1e-12));
  // The gantry's IK reaches it.
  EXPECT_EQ(inverseKinematics(gantry, X_WB, c.X_WT).size(), 1u);
  // A box lying tilted has no face up: no candidate.
  const Pose tilted = makePose(Vec3(0.5, 0.4, 0.1), Quat(Eigen::AngleAxisd(0.4, Vec3::UnitX())));
  EXPECT_TRUE(graspCandidates(gantry, X_WB, lid, tilted).empty());
  // Upside down: its bottom face points up and is grasped there.
  const Pose flipped = makePose(Vec3(0.5, 0.4, 0.15), Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX())));
  const auto flipped_candidates = graspCandidates(gantry, X_WB, lid, flipped);
  ASSERT_EQ(flipped_candidates.size(), 1u);
  EXPECT_EQ(flipped_candidates[0].face, GraspCandidate::Face::kBottom);
}

}  // namespace
}  // namespace dash
