// Gantry3: closed-form FK/IK (unique), body frames, and rejection of unreachable targets.
#include <gtest/gtest.h>

#include <random>

#include "engine/robots/kinematics.h"

namespace dash {
namespace {

const RobotModel& gantry() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib->get("gantry3");
}

JointVector jv(double x, double y, double z) {
  JointVector q(3);
  q << x, y, z;
  return q;
}

const Pose kBase = makePose(Vec3(1.0, 2.0, 0.75), Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ())));

TEST(GantryFk, ToolPointsDownAtTheConventionPosition) {
  const FkResult fk = forwardKinematics(gantry(), Pose::Identity(), jv(0.3, 0.2, 0.1));
  // TCP = (x, y, beam_height - ram_to_tcp - z) = (0.3, 0.2, 0.3); z_T = -z0, x_T = x0.
  EXPECT_LT((fk.X_WT.translation() - Vec3(0.3, 0.2, 0.3)).norm(), 1e-15);
  EXPECT_LT((fk.X_WT.linear().col(2) - Vec3(0, 0, -1)).norm(), 1e-15);
  EXPECT_LT((fk.X_WT.linear().col(0) - Vec3(1, 0, 0)).norm(), 1e-15);
  EXPECT_TRUE(fk.X_WF.isApprox(fk.X_WT));
  const FkResult moved = forwardKinematics(gantry(), kBase, jv(0.3, 0.2, 0.1));
  EXPECT_TRUE(moved.X_WT.isApprox(kBase * fk.X_WT, 1e-14));
}

TEST(GantryIk, RoundTripIsUniqueAndExact) {
  const RobotModel& m = gantry();
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int trial = 0; trial < 1000; ++trial) {
    JointVector q(3);
    for (int i = 0; i < 3; ++i) {
      q[i] = m.limits.position_min[i] + u(rng) * (m.limits.position_max[i] - m.limits.position_min[i]);
    }
    const Pose X_WT = forwardKinematics(m, kBase, q).X_WT;
    const auto sols = inverseKinematics(m, kBase, X_WT);
    ASSERT_EQ(sols.size(), 1u);
    EXPECT_LT((sols[0] - q).cwiseAbs().maxCoeff(), 1e-12);
  }
  // The limits themselves are reachable (corners of the box of travel).
  for (const JointVector& q : {m.limits.position_min, m.limits.position_max}) {
    const auto sols = inverseKinematics(m, kBase, forwardKinematics(m, kBase, q).X_WT);
    ASSERT_EQ(sols.size(), 1u);
    EXPECT_TRUE(m.withinLimits(sols[0], 0.0));
  }
}

TEST(GantryIk, RejectsOutOfLimitsAndWrongOrientations) {
  const RobotModel& m = gantry();
  const Pose X_WT = forwardKinematics(m, kBase, jv(0.5, 0.3, 0.15)).X_WT;
  // Out of limits on each axis (TCP z up = gantry z down).
  for (const Vec3& shift : std::array<Vec3, 4>{Vec3(0.6, 0, 0), Vec3(0, -0.31, 0), Vec3(0, 0, 0.2), Vec3(0, 0, -0.2)}) {
    Pose X = X_WT;
    X.translation() += kBase.linear() * shift;
    EXPECT_TRUE(inverseKinematics(m, kBase, X).empty()) << shift.transpose();
  }
  // Tool-down orientation is required to 1e-6 rad; a turn about the tool axis is a different pose.
  for (const Vec3& axis : std::array<Vec3, 3>{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()}) {
    Pose X = X_WT;
    X.linear() = X.linear() * Eigen::AngleAxisd(2e-6, axis).toRotationMatrix();
    EXPECT_TRUE(inverseKinematics(m, kBase, X).empty()) << axis.transpose();
    X = X_WT;
    X.linear() = X.linear() * Eigen::AngleAxisd(5e-7, axis).toRotationMatrix();
    EXPECT_EQ(inverseKinematics(m, kBase, X).size(), 1u) << axis.transpose();
  }
  Pose up = X_WT;
  up.linear() = kBase.linear();
  EXPECT_TRUE(inverseKinematics(m, kBase, up).empty());
}

TEST(GantryIk, ClampsWithinToleranceOfTheLimits) {
  const RobotModel& m = gantry();
  Pose X = forwardKinematics(m, Pose::Identity(), jv(1.0, 0.0, 0.3)).X_WT;
  X.translation() += Vec3(1e-10, -1e-10, -1e-10);  // just past max x, min y, max z
  JointVector q;
  ASSERT_EQ(inverseKinematicsGantry(m, Pose::Identity(), X, q), 1);
  EXPECT_TRUE(m.withinLimits(q, 0.0));
}

TEST(GantryBodyFrames, MovedBoxCentres) {
  const RobotModel& m = gantry();
  std::vector<Pose> frames(m.bodies.size());
  const JointVector q = jv(0.4, 0.25, 0.1);
  bodyFrames(m, kBase, q, frames);
  const std::vector<Vec3> expected = {
      Vec3(0.4, 0.30, 0.64),          // bridge: x only
      Vec3(0.4, 0.25, 0.60),          // carriage: x, y
      Vec3(0.4, 0.25, 0.55 - 0.1),    // ram: x, y, -z
      Vec3(0.4, 0.25, 0.415 - 0.1)};  // tool
  for (std::size_t i = 0; i < frames.size(); ++i) {
    EXPECT_LT((frames[i].translation() - kBase * expected[i]).norm(), 1e-14) << m.bodies[i].name;
    EXPECT_LT((frames[i].linear() - kBase.linear()).norm(), 1e-15);
    EXPECT_TRUE(m.bodies[i].box_center.isZero());  // the body frame is the box centre
  }
  // The tool box's bottom face is at the TCP.
  const Pose X_WT = forwardKinematics(m, kBase, q).X_WT;
  const Vec3 tool_bottom = frames[3] * Vec3(0, 0, -m.bodies[3].box_half_extents.z());
  EXPECT_LT((tool_bottom - X_WT.translation()).norm(), 1e-12);
}

}  // namespace
}  // namespace dash
