// Where a robot in the way waits (ARC's subproblem sends it there): home when that is clear, else a
// parking configuration clear of the robots at work.
#include <gtest/gtest.h>

#include <random>

#include "engine/collision/collision_queries.h"
#include "engine/conflict/parking.h"
#include "tests/conflict/two_arms.h"

namespace dash {
namespace {

using testing::TwoArms;

TEST(Parking, HomeWhenNothingIsInTheWay) {
  TwoArms arms;
  const JointVector q = parkingConfiguration(arms.world, arms.context, 0, {}, {}, arms.layout);
  EXPECT_TRUE(q.isApprox(arms.scene.robots[0].home));
}

TEST(Parking, AwayFromHomeWhenAnotherArmWorksThere) {
  TwoArms arms;
  // Robot 1 reaching over robot 0's home: valid alone, in collision with robot 0 at home.
  std::mt19937 rng(7);
  const RobotModel& model = *arms.scene.robots[1].model;
  std::optional<RobotState> worker;
  for (int attempt = 0; attempt < 50000 && !worker; ++attempt) {
    JointVector q(model.dof());
    for (int i = 0; i < model.dof(); ++i) q[i] = std::uniform_real_distribution<double>(-3.0, 3.0)(rng);
    const RobotState other{1, q, {}};
    if (robotInCollision(arms.world, arms.context, other, arms.layout)) continue;
    const RobotState pair[2] = {{0, arms.scene.robots[0].home, {}}, other};
    if (robotsInCollision(arms.world, arms.context, pair, arms.layout)) worker = other;
  }
  ASSERT_TRUE(worker.has_value());
  const JointVector q = parkingConfiguration(arms.world, arms.context, 0, {}, {*worker}, arms.layout);
  EXPECT_FALSE(q.isApprox(arms.scene.robots[0].home));
  const RobotState pair[2] = {{0, q, {}}, *worker};
  EXPECT_FALSE(robotsInCollision(arms.world, arms.context, pair, arms.layout));
}

}  // namespace
}  // namespace dash
