// The batched forward kinematics (engine/robots/batch_kinematics.h) against the scalar one, lane by
// lane: every body frame and the TCP of the UR5e and the gantry, and the sin/cos kernel against libm.
#include "engine/robots/batch_kinematics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "engine/core/rng.h"
#include "tests/common/robot_library.h"

namespace dash {
namespace {

Pose randomBase(Rng& rng) {
  const Vec3 axis = Vec3(rng.gaussian(0, 1), rng.gaussian(0, 1), rng.gaussian(0, 1)).normalized();
  return makePose(Vec3(rng.uniform(-3, 3), rng.uniform(-3, 3), rng.uniform(0, 1)),
                  Quat(Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), axis)));
}

JointVector randomConfiguration(const RobotModel& model, Rng& rng) {
  JointVector q(model.dof());
  for (int j = 0; j < model.dof(); ++j) q[j] = rng.uniform(model.limits.position_min[j], model.limits.position_max[j]);
  return q;
}

/// Largest difference (m, or unit-vector components) between the batched frames and bodyFrames /
/// forwardKinematics over `batches` batches of random configurations.
double largestDeviation(const RobotModel& model, int batches, std::uint64_t seed) {
  Rng rng(seed);
  double worst = 0.0;
  JointBatch qb;
  FrameBatch frames;
  std::vector<JointVector> qs(kBatchLanes);
  std::vector<Pose> scalar(model.bodies.size());
  for (int batch = 0; batch < batches; ++batch) {
    const Pose X_WB = randomBase(rng);
    for (int l = 0; l < kBatchLanes; ++l) {
      qs[static_cast<std::size_t>(l)] = randomConfiguration(model, rng);
      qb.set(l, qs[static_cast<std::size_t>(l)]);
    }
    batchFrames(model, X_WB, qb, frames);
    for (int l = 0; l < kBatchLanes; ++l) {
      bodyFrames(model, X_WB, qs[static_cast<std::size_t>(l)], scalar);
      for (std::size_t b = 0; b < scalar.size(); ++b) {
        const int f = bodyBatchFrame(model, static_cast<int>(b));
        for (int k = 0; k < 3; ++k) {
          worst = std::max(worst, std::abs(frames.p[f][k][l] - scalar[b].translation()[k]));
          for (int col = 0; col < 3; ++col)
            worst = std::max(worst, std::abs(frames.R[f][3 * col + k][l] - scalar[b].linear()(k, col)));
        }
      }
      const Pose X_WT = forwardKinematics(model, X_WB, qs[static_cast<std::size_t>(l)]).X_WT;
      for (int k = 0; k < 3; ++k) {
        worst = std::max(worst, std::abs(frames.tcp_p[k][l] - X_WT.translation()[k]));
        for (int col = 0; col < 3; ++col)
          worst = std::max(worst, std::abs(frames.tcp_R[3 * col + k][l] - X_WT.linear()(k, col)));
      }
    }
  }
  return worst;
}

TEST(BatchKinematics, UrFramesAndTcpMatchTheScalarKinematicsInEveryLane) {
  EXPECT_LT(largestDeviation(test::library()->get("ur5e"), 20000, 1), 1e-12);
}

TEST(BatchKinematics, GantryFramesAndTcpMatchTheScalarKinematicsInEveryLane) {
  EXPECT_LT(largestDeviation(test::library()->get("gantry3"), 20000, 2), 1e-12);
}

TEST(BatchKinematics, SinCosAgreesWithLibmToTwoUlpOfOneOverFourTurns) {
  Rng rng(3);
  double worst = 0.0;
  alignas(64) double x[kBatchLanes], s[kBatchLanes], c[kBatchLanes];
  for (int batch = 0; batch < 200000; ++batch) {
    for (double& v : x) v = rng.uniform(-4.0 * M_PI, 4.0 * M_PI);
    if (batch == 0) {  // the quadrant boundaries and exact zeros
      const double edges[kBatchLanes] = {0.0, M_PI / 4, -M_PI / 4, M_PI / 2, -M_PI, M_PI, 3 * M_PI / 4, 2 * M_PI};
      std::copy(edges, edges + kBatchLanes, x);
    }
    sinCosBatch(x, s, c);
    for (int l = 0; l < kBatchLanes; ++l) {
      worst = std::max({worst, std::abs(s[l] - std::sin(x[l])), std::abs(c[l] - std::cos(x[l]))});
    }
  }
  EXPECT_LE(worst, 4.5e-16);
}

}  // namespace
}  // namespace dash
