// UR5e closed-form IK: IK(FK(q)) recovers q, every solution reproduces the target, limits and the
// wrist-singularity rule.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "engine/robots/kinematics.h"

namespace dash {
namespace {

const RobotModel& ur5e() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib->get("ur5e");
}

double poseError(const Pose& A, const Pose& B) {
  return std::max((A.translation() - B.translation()).norm(), (A.linear() - B.linear()).norm());
}

double angleDistance(const JointVector& a, const JointVector& b) {
  double worst = 0.0;
  for (int i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(wrapToPi(a[i] - b[i])));
  return worst;
}

// Configurations this close to a singularity are skipped by the round-trip test: there the
// recovered joints lose accuracy like 5e-16 / distance (the returned solutions still reproduce the
// target, which is checked for every sample). 1e-5 keeps the recovery error of one singularity
// near 1e-10; where two singularities meet, the errors multiply.
constexpr double kSingularMargin = 1e-5;

// Distances to the three UR singularities: shoulder (the wrist point p5 in the plane of z0 and z1,
// i.e. its component along x1 is zero), elbow (sin q3) and wrist (sin q5).
std::array<double, 3> singularDistances(const RobotModel& m, const JointVector& q) {
  std::array<Pose, kUrFrames> X;
  urFrames(m, Pose::Identity(), q, X);
  const Vec3 p5 = X[5].translation();
  const Vec3 x1 = X[1].linear().col(0);
  return {std::abs(p5.dot(x1)), std::abs(std::sin(q[2])), std::abs(std::sin(q[4]))};
}

bool nearSingular(const RobotModel& m, const JointVector& q, double margin = kSingularMargin) {
  const auto d = singularDistances(m, q);
  return *std::min_element(d.begin(), d.end()) < margin;
}

TEST(UrIk, RoundTripTenThousandRandomConfigurations) {
  const RobotModel& m = ur5e();
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  const Pose X_WB = makePose(Vec3(0.3, -0.2, 0.1), Quat(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized())));
  std::array<JointVector, kUrMaxIkSolutions> sols;
  int checked = 0;
  int skipped = 0;
  double worst_recovery = 0.0;
  double worst_fk = 0.0;
  for (int trial = 0; trial < 10000; ++trial) {
    JointVector q(6);
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    const Pose X_WT = forwardKinematics(m, X_WB, q).X_WT;
    const int n = inverseKinematicsUr(m, X_WB, X_WT, sols);
    ASSERT_GE(n, 1) << q.transpose();
    ASSERT_LE(n, 8);
    for (int k = 0; k < n; ++k) {
      const JointVector& s = sols[static_cast<std::size_t>(k)];
      ASSERT_EQ(s.size(), 6);
      EXPECT_TRUE(m.withinLimits(s, 0.0));
      EXPECT_TRUE((s.array().abs() <= M_PI).all()) << s.transpose();
      const double err = poseError(forwardKinematics(m, X_WB, s).X_WT, X_WT);
      worst_fk = std::max(worst_fk, err);
      EXPECT_LT(err, 1e-9) << "q " << q.transpose() << "\nsol " << s.transpose();
    }
    if (nearSingular(m, q)) {
      ++skipped;
      continue;
    }
    ++checked;
    double best = 1e9;
    for (int k = 0; k < n; ++k) best = std::min(best, angleDistance(sols[static_cast<std::size_t>(k)], q));
    worst_recovery = std::max(worst_recovery, best);
    EXPECT_LT(best, 1e-9) << q.transpose();
  }
  EXPECT_GT(checked, 9900);
  std::printf("checked %d, skipped %d near singularities; worst recovery %.3g rad, worst FK error %.3g\n",
              checked, skipped, worst_recovery, worst_fk);
}

TEST(UrIk, VectorVersionMatchesArrayVersion) {
  const RobotModel& m = ur5e();
  JointVector q(6);
  q << 0.3, -1.2, 1.1, -0.4, 0.8, 2.9;
  const Pose X_WT = forwardKinematics(m, Pose::Identity(), q).X_WT;
  std::array<JointVector, kUrMaxIkSolutions> sols;
  const int n = inverseKinematicsUr(m, Pose::Identity(), X_WT, sols);
  const auto v = inverseKinematics(m, Pose::Identity(), X_WT);
  ASSERT_EQ(static_cast<int>(v.size()), n);
  for (int k = 0; k < n; ++k) EXPECT_EQ(v[static_cast<std::size_t>(k)], sols[static_cast<std::size_t>(k)]);
}

TEST(UrIk, HomePoseHasEightSolutionsIncludingHome) {
  // Home: flange pointing straight down, q5 = -pi/2 (not singular).
  const RobotModel& m = ur5e();
  JointVector home(6);
  home << 0, -M_PI / 2, M_PI / 2, -M_PI / 2, -M_PI / 2, 0;
  const Pose X_WT = forwardKinematics(m, Pose::Identity(), home).X_WT;
  const auto sols = inverseKinematics(m, Pose::Identity(), X_WT);
  EXPECT_EQ(sols.size(), 8u);
  double best = 1e9;
  for (const auto& s : sols) best = std::min(best, angleDistance(s, home));
  EXPECT_LT(best, 1e-12);
}

TEST(UrIk, WristSingularityFixesQ6ToTheReference) {
  const RobotModel& m = ur5e();
  for (double q5 : {0.0, M_PI}) {
    JointVector q(6);
    q << 0.4, -1.3, 1.2, -0.6, q5, 0.9;
    const Pose X_WT = forwardKinematics(m, Pose::Identity(), q).X_WT;
    // Only q4 + q6 (q5 = 0) or q4 - q6 (q5 = pi) is determined; q6 is set to the reference.
    auto check = [&](double q6_reference) {
      std::array<JointVector, kUrMaxIkSolutions> sols;
      const int n = inverseKinematicsUr(m, Pose::Identity(), X_WT, sols, q6_reference);
      // Only the shoulder branch of q is singular (the other one has a different z1); on it there is
      // one wrist branch (not two copies), times two elbows.
      int singular = 0;
      bool found = false;
      for (int k = 0; k < n; ++k) {
        const JointVector& s = sols[static_cast<std::size_t>(k)];
        EXPECT_LT(poseError(forwardKinematics(m, Pose::Identity(), s).X_WT, X_WT), 1e-12);
        if (std::abs(std::sin(s[4])) > 1e-6) continue;
        ++singular;
        EXPECT_NEAR(s[5], wrapToPi(q6_reference), 1e-15);
        EXPECT_TRUE(s[4] == 0.0 || std::abs(s[4]) == M_PI) << s[4];
        if (angleDistance(s, q) < 1e-9) found = true;
      }
      EXPECT_EQ(singular, 2);
      // With the original q6 as the reference, the original q is among the solutions. (Another
      // reference moves the wrist point d5 z4 with q4, so q2, q3 change too.)
      if (q6_reference == q[5]) {
        EXPECT_TRUE(found) << "q5 " << q5;
      }
    };
    check(0.0);
    check(0.9);  // the original q6: recovers q exactly
    check(-2.5);
    check(7.0);  // wrapped into [-pi, pi]
  }
}

TEST(UrIk, UnreachableTargetsGiveNoSolution) {
  const RobotModel& m = ur5e();
  EXPECT_TRUE(inverseKinematics(m, Pose::Identity(), makePose(Vec3(2.0, 0.0, 0.3))).empty());
  EXPECT_TRUE(inverseKinematics(m, Pose::Identity(), makePose(Vec3(0.0, 0.0, 1.5))).empty());
  // Wrist point on the base axis: inside the shoulder's dead cylinder of radius d4.
  const Pose down = makePose(Vec3(0.0, 0.0, 0.5), Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX())));
  EXPECT_TRUE(inverseKinematics(m, Pose::Identity(), down).empty());
}

TEST(UrIk, NarrowLimitsFilterSolutions) {
  RobotModel m = ur5e();
  JointVector q(6);
  q << 0.3, -1.2, 1.1, -0.4, 0.8, 2.9;
  const Pose X_WT = forwardKinematics(m, Pose::Identity(), q).X_WT;
  m.limits.position_min[2] = 0.0;  // elbow only positive: half the solutions go
  const auto sols = inverseKinematics(m, Pose::Identity(), X_WT);
  EXPECT_EQ(sols.size(), 4u);
  for (const auto& s : sols) EXPECT_TRUE(m.withinLimits(s, 0.0));
  // Limits in [0, 2 pi] on q6: wrapped values are shifted by 2 pi instead of dropped.
  m.limits.position_min[5] = 0.0;
  m.limits.position_max[5] = 2 * M_PI;
  for (const auto& s : inverseKinematics(m, Pose::Identity(), X_WT)) {
    EXPECT_GE(s[5], 0.0);
    EXPECT_LT(poseError(forwardKinematics(m, Pose::Identity(), s).X_WT, X_WT), 1e-9);
  }
}

// Just outside the margin of one singularity (the others far away) the joints are still recovered.
TEST(UrIk, RecoversConfigurationsJustOutsideTheSingularMargin) {
  const RobotModel& m = ur5e();
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::array<JointVector, kUrMaxIkSolutions> sols;
  double worst = 0.0;
  int checked = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    JointVector q(6);
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    const double offset = 2.0 * kSingularMargin * (unit(rng) < 0.5 ? -1.0 : 1.0);
    const double base = unit(rng) < 0.5 ? 0.0 : M_PI;
    const int joint = trial % 2 == 0 ? 4 : 2;  // wrist or elbow
    q[joint] = wrapToPi(base + offset);
    auto d = singularDistances(m, q);
    d[joint == 2 ? 1 : 2] = 1.0;
    if (*std::min_element(d.begin(), d.end()) < 1e-2) continue;  // only one singularity nearby
    ++checked;
    const Pose X_WT = forwardKinematics(m, Pose::Identity(), q).X_WT;
    const int n = inverseKinematicsUr(m, Pose::Identity(), X_WT, sols);
    double best = 1e9;
    for (int k = 0; k < n; ++k) {
      const JointVector& s = sols[static_cast<std::size_t>(k)];
      best = std::min(best, angleDistance(s, q));
      EXPECT_LT(poseError(forwardKinematics(m, Pose::Identity(), s).X_WT, X_WT), 1e-9);
    }
    worst = std::max(worst, best);
    EXPECT_LT(best, 1e-9) << q.transpose();
  }
  EXPECT_GT(checked, 3000);
  std::printf("worst recovery at 2x the singular margin: %.3g rad\n", worst);
}

// At combined singularities (stretched or folded elbow, aligned or nearly aligned wrist, both) IK
// still returns solutions, and they reproduce the target.
TEST(UrIk, CombinedSingularitiesStillSolve) {
  const RobotModel& m = ur5e();
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  // Near an aligned wrist q6 is ill-conditioned, and p4 can miss the elbow's reach by rounding.
  const double wrist_offsets[] = {0.0, 1e-13, 1e-11, 1e-9, 1e-7};
  for (int trial = 0; trial < 2000; ++trial) {
    JointVector q(6);
    for (int i = 0; i < 6; ++i) q[i] = angle(rng);
    if (trial % 3 != 1) q[2] = (trial / 3) % 2 == 0 ? 0.0 : M_PI;
    if (trial % 3 != 2) q[4] = ((trial / 6) % 2 == 0 ? 0.0 : -M_PI) + wrist_offsets[(trial / 12) % 5];
    if (singularDistances(m, q)[0] < 1e-6) continue;
    const Pose X_WT = forwardKinematics(m, Pose::Identity(), q).X_WT;
    const auto sols = inverseKinematics(m, Pose::Identity(), X_WT);
    ASSERT_FALSE(sols.empty()) << q.transpose();
    for (const auto& s : sols) {
      EXPECT_LT(poseError(forwardKinematics(m, Pose::Identity(), s).X_WT, X_WT), 1e-9) << q.transpose();
    }
  }
}

}  // namespace
}  // namespace dash
