// Forward kinematics and body frames against hand-computed poses and a naive DH chain.
#include <gtest/gtest.h>

#include <random>

#include "engine/robots/kinematics.h"

namespace dash {
namespace {

const RobotModel& ur5e() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib->get("ur5e");
}

JointVector jv(std::initializer_list<double> v) {
  JointVector q(static_cast<Eigen::Index>(v.size()));
  Eigen::Index i = 0;
  for (double x : v) q[i++] = x;
  return q;
}

// The DH chain written out with Eigen transforms, as an independent reference.
Pose naiveDh(const RobotModel& m, const Pose& X_WB, const JointVector& q, int frames) {
  Pose X = X_WB;
  for (int i = 0; i < frames; ++i) {
    X = X * Eigen::AngleAxisd(q[i], Vec3::UnitZ()) * Eigen::Translation3d(0, 0, m.dh.d[i]) *
        Eigen::Translation3d(m.dh.a[i], 0, 0) * Eigen::AngleAxisd(m.dh.alpha[i], Vec3::UnitX());
  }
  return X;
}

TEST(UrFk, ZeroConfigurationByHand) {
  // q = 0: frame 1 at z = d1 with z1 = -y0; the arm links stretch along -x (a2 + a3 = -0.8172);
  // d4 moves along -y, d5 down along -z, d6 along -y again. Flange axes: x = x0, y = z0, z = -y0.
  const FkResult fk = forwardKinematics(ur5e(), Pose::Identity(), JointVector::Zero(6));
  EXPECT_LT((fk.X_WF.translation() - Vec3(-0.8172, -0.2329, 0.0628)).norm(), 1e-12)
      << fk.X_WF.translation().transpose();
  Eigen::Matrix3d R;
  R << 1, 0, 0, 0, 0, -1, 0, 1, 0;
  EXPECT_LT((fk.X_WF.linear() - R).norm(), 1e-15);
  EXPECT_LT((fk.X_WT.translation() - Vec3(-0.8172, -0.2329 - 0.157, 0.0628)).norm(), 1e-12);
  EXPECT_LT((fk.X_WT.linear() - R).norm(), 1e-15);
}

TEST(UrFk, HomeConfigurationByHand) {
  // Home [0, -pi/2, pi/2, -pi/2, -pi/2, 0]: upper arm vertical (z = d1 - a2), forearm along -x,
  // flange pointing down. Flange rotation: a half turn about (1, 1, 0)/sqrt(2).
  const JointVector q = jv({0, -M_PI / 2, M_PI / 2, -M_PI / 2, -M_PI / 2, 0});
  const FkResult fk = forwardKinematics(ur5e(), Pose::Identity(), q);
  const Vec3 p_flange(-0.3922 - 0.0997, -0.1333, 0.1625 + 0.425 - 0.0996);
  EXPECT_LT((fk.X_WF.translation() - p_flange).norm(), 1e-12) << fk.X_WF.translation().transpose();
  Eigen::Matrix3d R;
  R << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  EXPECT_LT((fk.X_WF.linear() - R).norm(), 1e-12);
  EXPECT_LT((fk.X_WT.translation() - (p_flange - Vec3(0, 0, 0.157))).norm(), 1e-12);
  const Quat quat(fk.X_WF.linear());
  EXPECT_NEAR(std::abs(quat.x()), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(std::abs(quat.y()), std::sqrt(0.5), 1e-12);
}

TEST(UrFk, BaseMountPoseIsApplied) {
  const Pose X_WB = makePose(Vec3(1.0, -2.0, 0.5), Quat(Eigen::AngleAxisd(0.7, Vec3(0.2, 0.3, 1).normalized())));
  const JointVector q = jv({0.3, -1.1, 1.4, -0.2, 0.9, -2.5});
  const FkResult local = forwardKinematics(ur5e(), Pose::Identity(), q);
  const FkResult world = forwardKinematics(ur5e(), X_WB, q);
  EXPECT_TRUE((X_WB * local.X_WT).isApprox(world.X_WT, 1e-12));
  EXPECT_TRUE((X_WB * local.X_WF).isApprox(world.X_WF, 1e-12));
}

TEST(UrFk, MatchesNaiveDhChainAndBodyFrames) {
  const RobotModel& m = ur5e();
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  const Pose X_WB = makePose(Vec3(0.4, 0.1, 0.02), Quat(Eigen::AngleAxisd(1.2, Vec3::UnitZ())));
  std::vector<Pose> frames(m.bodies.size());
  for (int trial = 0; trial < 200; ++trial) {
    JointVector q(6);
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    const FkResult fk = forwardKinematics(m, X_WB, q);
    const Pose X_W6 = naiveDh(m, X_WB, q, 6);
    EXPECT_LT((fk.X_WF.matrix() - X_W6.matrix()).norm(), 1e-13);
    EXPECT_LT((fk.X_WT.matrix() - (X_W6 * m.dh.X_FT).matrix()).norm(), 1e-13);
    bodyFrames(m, X_WB, q, frames);
    for (std::size_t b = 0; b < m.bodies.size(); ++b) {
      const Pose expected = naiveDh(m, X_WB, q, m.bodies[b].frame);
      EXPECT_LT((frames[b].matrix() - expected.matrix()).norm(), 1e-13) << m.bodies[b].name;
    }
    std::array<Pose, kUrFrames> all;
    urFrames(m, X_WB, q, all);
    EXPECT_TRUE(all[0].isApprox(X_WB, 1e-15));
    EXPECT_LT((all[6].matrix() - fk.X_WF.matrix()).norm(), 1e-15);
  }
}

TEST(UrFk, BodyFramesPlaceCapsulesOnTheArm) {
  // At q = 0 the upper_arm capsule (frame 2, from (0.425, 0, 0.138) to (0, 0, 0.138)) must span
  // from the shoulder (x = 0) to the elbow (x = -0.425), offset 0.138 along z2 = -y0.
  const RobotModel& m = ur5e();
  std::vector<Pose> frames(m.bodies.size());
  bodyFrames(m, Pose::Identity(), JointVector::Zero(6), frames);
  const auto i = static_cast<std::size_t>(m.bodyIndex("upper_arm"));
  const Vec3 a = frames[i] * m.bodies[i].capsule.a;
  const Vec3 b = frames[i] * m.bodies[i].capsule.b;
  EXPECT_LT((a - Vec3(0.0, -0.138, 0.1625)).norm(), 1e-12) << a.transpose();
  EXPECT_LT((b - Vec3(-0.425, -0.138, 0.1625)).norm(), 1e-12) << b.transpose();
}

}  // namespace
}  // namespace dash
