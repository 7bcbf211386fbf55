// Cartesian approach paths (cartesian_path.h) against the placement that pressed a held item into its
// pedestal (issue 36, item 9): stocking 3 layers / 18 objects, seed 1, Lazy-DaSH seed 1, ur5e_0 putting
// new_0 (a 4 cm cube) into the deepest slot of cubby c2 from 35 cm back and 15 mm up. Its one
// joint-space segment q_pre -> q took the cube 0.84 mm into shelf_c2_l0_d2_pedestal.
#include "engine/robots/cartesian_path.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "engine/robots/kinematics.h"
#include "tests/common/robot_library.h"

namespace dash {
namespace {

const RobotModel& ur5e() { return test::library()->get("ur5e"); }

JointVector jv(std::initializer_list<double> v) {
  JointVector q(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) q[i++] = x;
  return q;
}

// The scene's robot base, the grasp and the support, as the scene and plan files have them.
const Pose kBase = makePose(Vec3(0.0, -0.8, 0.0), quatFromXYZW({0.0, 0.0, 0.7071067811865477, 0.7071067811865475}));
const Pose kGrasp = makePose(Vec3::Zero(), quatFromXYZW({0.5, 0.5, -0.5, 0.5}));  // X_TO of new_0
constexpr double kHalf = 0.02;                                                    // the cube's half size, m
constexpr double kSupportTop = 0.21;                                              // the pedestal's top face, m
const JointVector kQPre =
    jv({2.267870406076017, -1.0739551346086238, 2.5606670430722103, 1.6548807451262064, -0.6970740792811211, 0.0});
const JointVector kQ =
    jv({2.6918335950351437, -0.8024386068897624, 1.8402394654282053, 2.1037917950513503, -1.121037268240248, 0.0});

/// Height of the held cube's lowest corner above the pedestal's top at q, m.
double bottomGap(const JointVector& q) {
  const Pose X_WO = forwardKinematics(ur5e(), kBase, q).X_WT * kGrasp;
  double lowest = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner((c & 1 ? 1 : -1) * kHalf, (c & 2 ? 1 : -1) * kHalf, (c & 4 ? 1 : -1) * kHalf);
    lowest = std::min(lowest, (X_WO * corner).z());
  }
  return lowest - kSupportTop;
}

/// The lowest gap along a path whose points are joined by joint-space segments, sampled every 1/400
/// of each segment.
double lowestGap(const std::vector<JointVector>& path) {
  double lowest = bottomGap(path.front());
  for (std::size_t i = 1; i < path.size(); ++i)
    for (int k = 1; k <= 400; ++k)
      lowest = std::min(lowest, bottomGap(path[i - 1] + (k / 400.0) * (path[i] - path[i - 1])));
  return lowest;
}

TEST(CartesianPath, TheCubbyPlacementThatScrapedNowStaysAboveThePedestalAndEndsOnIt) {
  // The case itself: the single joint-space segment goes below the pedestal's top.
  EXPECT_LT(lowestGap({kQPre, kQ}), -5e-4);
  const auto path = cartesianPath(ur5e(), kBase, kQPre, kQ);
  ASSERT_TRUE(path.has_value());
  ASSERT_GE(path->size(), 3u);
  EXPECT_EQ(path->front(), kQPre);
  EXPECT_EQ(path->back(), kQ);
  EXPECT_GT(lowestGap(*path), -1e-4);                  // never more than 0.1 mm below the support's top
  EXPECT_LT(std::abs(bottomGap(path->back())), 1e-4);  // and ends on it
  // Every sampled TCP position lies on the straight line between the ends.
  const Vec3 a = forwardKinematics(ur5e(), kBase, kQPre).X_WT.translation();
  const Vec3 b = forwardKinematics(ur5e(), kBase, kQ).X_WT.translation();
  const Vec3 u = (b - a).normalized();
  for (std::size_t i = 1; i < path->size(); ++i)
    for (int k = 0; k <= 20; ++k) {
      const Vec3 p = forwardKinematics(ur5e(), kBase, (*path)[i - 1] + (k / 20.0) * ((*path)[i] - (*path)[i - 1]))
                         .X_WT.translation();
      EXPECT_LT(((p - a) - (p - a).dot(u) * u).norm(), 2e-5);
    }
}

TEST(CartesianPath, TheRetreatAfterAPickIsTheReversedLine) {
  // Lifting the cube off the pedestal: the same line, the other way.
  const auto path = cartesianPath(ur5e(), kBase, kQ, kQPre);
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->front(), kQ);
  EXPECT_EQ(path->back(), kQPre);
  EXPECT_GT(lowestGap(*path), -1e-4);
}

TEST(CartesianPath, TheBackOffLineOfBothPlannersStaysAboveThePedestalWithFewerWaypoints) {
  // backOffLine (what both planners check and emit, from the transition configuration out): the
  // deviation allowed grows away from the pedestal, where the line is high above it.
  const auto line = backOffLine(ur5e(), kBase, kQ, kQPre);
  ASSERT_TRUE(line.has_value());
  EXPECT_EQ(line->front(), kQ);
  EXPECT_EQ(line->back(), kQPre);
  EXPECT_GT(lowestGap(*line), -1e-4);
  EXPECT_LT(std::abs(bottomGap(line->front())), 1e-4);
  EXPECT_LT(line->size(), cartesianPath(ur5e(), kBase, kQ, kQPre)->size());
  EXPECT_EQ(backOffPath(ur5e(), kBase, kQ, kQPre), *line);
}

TEST(CartesianPath, AnotherIkBranchAtTheEndIsRefused) {
  // The same back-off pose on another IK branch (a wrist flip) is not joined by the line.
  const Pose X_pre = forwardKinematics(ur5e(), kBase, kQPre).X_WT;
  int refused = 0;
  for (const JointVector& other : inverseKinematics(ur5e(), kBase, X_pre)) {
    if ((other - kQPre).cwiseAbs().maxCoeff() < 1e-6) continue;
    if (!cartesianPath(ur5e(), kBase, other, kQ)) ++refused;
  }
  EXPECT_GT(refused, 0);
}

TEST(CartesianPath, EqualEndsAreOnePoint) {
  const auto path = cartesianPath(ur5e(), kBase, kQ, kQ);
  ASSERT_TRUE(path.has_value());
  EXPECT_EQ(path->size(), 1u);
}

}  // namespace
}  // namespace dash
