#include <gtest/gtest.h>

#include <array>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/core/rng.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

/// UR5e at the origin on the table; a 5 mm thin wall standing in the vertical plane the TCP crosses
/// when joint 1 passes through 0, between the end points joint 1 = -0.6 and +0.6.
struct ThinWall {
  Scene scene = test::emptyScene();
  JointVector q0 = test::urHome();
  JointVector q1 = test::urHome();

  ThinWall() {
    test::addTable(scene);
    test::addUr(scene, "ur", Pose::Identity());
    const Vec3 p_tcp = forwardKinematics(*scene.library->find("ur5e"), Pose::Identity(), test::urHome()).X_WT.translation();
    const double radius = p_tcp.head<2>().norm();
    const double heading = std::atan2(p_tcp.y(), p_tcp.x());
    // 5 mm thick, from 0.1 to 1.1 times the TCP's distance from the base axis, around the TCP's height.
    const Pose X_WW = makePose(Vec3(0.6 * radius * std::cos(heading), 0.6 * radius * std::sin(heading), p_tcp.z()),
                               Quat(Eigen::AngleAxisd(heading, Vec3::UnitZ())));
    test::addObstacle(scene, "thin_wall", Vec3(radius, 0.005, 0.1), X_WW);
    q0[0] = -0.6;
    q1[0] = 0.6;
  }
};

TEST(Segments, CatchAThinWallBetweenValidEndPoints) {
  ThinWall setup;
  const CollisionWorld world(setup.scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::empty(setup.scene);
  ASSERT_FALSE(robotInCollision(world, context, {.robot = 0, .q = setup.q0}, layout));
  ASSERT_FALSE(robotInCollision(world, context, {.robot = 0, .q = setup.q1}, layout));
  ASSERT_TRUE(robotInCollision(world, context, {.robot = 0, .q = test::urHome()}, layout));
  context.resetCounters();
  CollisionReport report;
  EXPECT_TRUE(segmentInCollision(world, context, {.robot = 0, .q = setup.q0}, setup.q1, layout, &report));
  EXPECT_EQ(report.b, CollisionElement::obstacle(1));
  EXPECT_GT(report.segment_fraction, 0.3);
  EXPECT_LT(report.segment_fraction, 0.7);
  EXPECT_EQ(context.counters().segment_checks, 1u);
  // Coarse to fine: the midpoint is the third configuration checked, after the two end points.
  EXPECT_EQ(context.counters().configuration_checks, 3u);
  // Reversed direction, and with the end points known valid.
  EXPECT_TRUE(segmentInCollision(world, context, {.robot = 0, .q = setup.q1}, setup.q0, layout, nullptr,
                                 {.check_endpoints = false}));
  // A coarse resolution that only looks at the end points misses the wall: the resolution matters.
  EXPECT_FALSE(segmentInCollision(world, context, {.robot = 0, .q = setup.q0}, setup.q1, layout, nullptr,
                                  {.resolution = 100.0}));
}

TEST(Segments, FreeSegmentAwayFromEverythingNeedsNoIntermediateChecks) {
  Scene scene = test::emptyScene();
  test::addUr(scene, "ur", Pose::Identity());
  test::addObstacle(scene, "far", Vec3(0.1, 0.1, 0.1), makePose(Vec3(3.0, 0.0, 0.0)));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  // Arm straight up, turning about the base: no self pair comes near.
  const JointVector q0 = test::joints({0, -M_PI / 2, 0, -M_PI / 2, 0, 0});
  JointVector q1 = q0;
  q1[0] = 1.0;
  EXPECT_FALSE(segmentInCollision(world, context, {.robot = 0, .q = q0}, q1, ObjectLayout::empty(scene)));
  // The far obstacle is dropped at once; the self pairs' swept boxes stop meeting after a few halvings,
  // so only a small fraction of the steps is ever posed and checked.
  const int steps = segmentSteps(world, 0, q0, q1, {});
  EXPECT_GT(steps, 100);
  EXPECT_LT(context.counters().configuration_checks, 2u + static_cast<unsigned>(steps) / 4);
  EXPECT_EQ(context.counters().narrowphase_calls, 0u);
}

/// Positions of the farthest-out capsule surface points, box corners and the TCP of robot 0 at q.
std::vector<Vec3> bodyPoints(const Scene& scene, const JointVector& q) {
  const RobotModel& model = *scene.robots[0].model;
  std::vector<Pose> frames(model.bodies.size());
  bodyFrames(model, scene.robots[0].X_WB, q, frames);
  std::vector<Vec3> points;
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const CollisionBody& body = model.bodies[b];
    if (body.kind == CollisionBody::Kind::kCapsule) {
      for (const Vec3& e : {body.capsule.a, body.capsule.b}) {
        for (int axis = 0; axis < 3; ++axis) {
          for (const double s : {-1.0, 1.0}) points.push_back(frames[b] * (e + s * body.capsule.radius * Vec3::Unit(axis)));
        }
      }
    } else {
      for (int k = 0; k < 8; ++k) {
        const Vec3 corner((k & 1 ? 1 : -1) * body.box_half_extents.x(), (k & 2 ? 1 : -1) * body.box_half_extents.y(),
                          (k & 4 ? 1 : -1) * body.box_half_extents.z());
        points.push_back(frames[b] * (body.box_center + corner));
      }
    }
  }
  points.push_back(forwardKinematics(model, scene.robots[0].X_WB, q).X_WT.translation());
  return points;
}

TEST(Segments, NoPointMovesMoreThanTheResolutionBetweenChecks) {
  Scene scene = test::emptyScene();
  test::addUr(scene, "ur", test::yawPose(0.2, -0.1, 0.3, 0.4));
  const CollisionWorld world(scene);
  Rng rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    JointVector q0(6);
    JointVector q1(6);
    for (int i = 0; i < 6; ++i) {
      q0[i] = rng.uniform(-M_PI, M_PI);
      q1[i] = q0[i] + rng.uniform(-1.0, 1.0);
    }
    const int n = segmentSteps(world, 0, q0, q1, {});
    double worst = 0.0;
    for (int k = 0; k < n; ++k) {
      const auto at_step = bodyPoints(scene, q0 + (static_cast<double>(k) / n) * (q1 - q0));
      for (int sub = 1; sub <= 8; ++sub) {
        const double t = (k + sub / 8.0) / n;
        const auto p = bodyPoints(scene, q0 + t * (q1 - q0));
        for (std::size_t i = 0; i < p.size(); ++i) worst = std::max(worst, (p[i] - at_step[i]).norm());
      }
    }
    EXPECT_LE(worst, kSegmentResolution) << "trial " << trial << " steps " << n;
    EXPECT_GT(worst, 0.1 * kSegmentResolution) << "bound far too loose, trial " << trial;
  }
}

TEST(Segments, HeldObjectCountsInTheResolution) {
  Scene scene = test::emptyScene();
  test::addUr(scene, "ur", Pose::Identity());
  test::addCube(scene, "cube", 0.04, Pose::Identity());
  const CollisionWorld world(scene);
  const JointVector q0 = test::urHome();
  JointVector q1 = q0;
  q1[5] += 1.0;  // only the last wrist joint turns
  const HeldObject near{.object = 0, .X_TO = Pose::Identity()};
  const HeldObject far{.object = 0, .X_TO = makePose(Vec3(0.5, 0.0, 0.0))};
  EXPECT_GT(segmentSteps(world, 0, q0, q1, far), segmentSteps(world, 0, q0, q1, near) + 40);
}

TEST(Segments, TwoArmsSwingingIntoEachOther) {
  Scene scene = test::emptyScene();
  test::addTable(scene);
  // Facing each other 1.1 m apart; with q = 0 a UR arm lies horizontal along its base's -x axis.
  test::addUr(scene, "a", test::yawPose(0.0, 0.0, 0.0, M_PI), test::joints({0, 0, 0, 0, 0, 0}));
  test::addUr(scene, "b", test::yawPose(1.1, 0.0, 0.0, 0.0), test::joints({0, 0, 0, 0, 0, 0}));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::empty(scene);
  // Each arm swings from one side of the line between the bases to the other (joint 1 from +1 to -1):
  // a from +y to -y, b from -y to +y. They cross that line at the same moment.
  const JointVector side_1 = test::joints({1.0, 0, 0, 0, 0, 0});
  const JointVector side_2 = test::joints({-1.0, 0, 0, 0, 0, 0});
  const std::array<RobotState, 2> start{RobotState{.robot = 0, .q = side_1}, RobotState{.robot = 1, .q = side_1}};
  const std::array<RobotState, 2> end{RobotState{.robot = 0, .q = side_2}, RobotState{.robot = 1, .q = side_2}};
  CollisionReport report;
  ASSERT_FALSE(robotsInCollision(world, context, start, layout, &report)) << describe(report, scene);
  ASSERT_FALSE(robotsInCollision(world, context, end, layout, &report)) << describe(report, scene);
  const std::array<RobotMotion, 2> motions{RobotMotion{start[0], side_2}, RobotMotion{start[1], side_2}};
  ASSERT_TRUE(motionsInCollision(world, context, motions, layout, &report));
  EXPECT_EQ(report.a.kind, CollisionElement::Kind::kRobotBody);
  EXPECT_EQ(report.b.kind, CollisionElement::Kind::kRobotBody);
  EXPECT_NE(report.a.robot, report.b.robot);
  EXPECT_NEAR(report.segment_fraction, 0.5, 0.2);
  // Each motion alone is free.
  EXPECT_FALSE(segmentInCollision(world, context, start[0], side_2, layout));
  EXPECT_FALSE(segmentInCollision(world, context, start[1], side_2, layout));
  // If b turns its arm away (joint 1 = pi: along +x) and stays, a swings through: free.
  const JointVector away = test::joints({M_PI, 0, 0, 0, 0, 0});
  const std::array<RobotMotion, 2> one_moves{RobotMotion{start[0], side_2}, RobotMotion{{.robot = 1, .q = away}, away}};
  EXPECT_FALSE(motionsInCollision(world, context, one_moves, layout, &report)) << describe(report, scene);
  // Robot against robot only (the scheduler's check): the same crossing is found.
  EXPECT_TRUE(motionsInCollision(world, context, motions, layout, &report, {.scope = CheckScope::kRobotsOnly}));
  EXPECT_EQ(report.a.kind, CollisionElement::Kind::kRobotBody);
  EXPECT_EQ(report.b.kind, CollisionElement::Kind::kRobotBody);
}

// CheckScope::kRobotsOnly looks at robot pairs only: an arm swinging through a thin wall beside a
// robot far away is a collision for the static scope and none for the robots-only one.
TEST(Segments, RobotsOnlyScopeIgnoresWhatNeverMoves) {
  ThinWall setup;
  test::addUr(setup.scene, "far", test::yawPose(5.0, 0.0, 0.0));
  const CollisionWorld world(setup.scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::empty(setup.scene);
  const std::array<RobotMotion, 2> motions{RobotMotion{{.robot = 0, .q = setup.q0}, setup.q1},
                                           RobotMotion{{.robot = 1, .q = test::urHome()}, test::urHome()}};
  EXPECT_TRUE(motionsInCollision(world, context, motions, layout, nullptr, {.scope = CheckScope::kStaticOnly}));
  context.resetCounters();
  EXPECT_FALSE(motionsInCollision(world, context, motions, layout, nullptr, {.scope = CheckScope::kRobotsOnly}));
  // Apart: nothing between the end points is looked at.
  EXPECT_LE(context.counters().configuration_checks, 2u);
}

TEST(Segments, MotionsApartAreCheckedOneByOne) {
  Scene scene = test::emptyScene();
  test::addUr(scene, "a", test::yawPose(0.0, 0.0, 0.0));
  test::addUr(scene, "b", test::yawPose(5.0, 0.0, 0.0));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const JointVector q0 = test::joints({0, -M_PI / 2, 0, -M_PI / 2, 0, 0});
  JointVector q1 = q0;
  q1[0] = 0.5;
  const std::array<RobotMotion, 2> motions{RobotMotion{{.robot = 0, .q = q0}, q1}, RobotMotion{{.robot = 1, .q = q0}, q1}};
  EXPECT_FALSE(motionsInCollision(world, context, motions, ObjectLayout::empty(scene)));
  // Far apart: each robot's motion is refined alone (few checks), never both at every step.
  const int steps = segmentSteps(world, 0, q0, q1, {});
  EXPECT_LT(context.counters().configuration_checks, static_cast<unsigned>(steps) / 2);
}

// The planners' query with other robots parked (motionsAmongParked) poses the parked robots once and
// checks them against the mover only. Where the parked robots stand free of everything, it gives the
// verdict of the full check with the parked robots as motions that stay put (motionsInCollision, which
// re-poses and re-checks every robot at every step); a parked robot that touches an obstacle does not
// make a mover far from it collide.
TEST(Segments, ParkedRobotsAreCheckedAgainstTheMoverOnly) {
  Scene scene = test::emptyScene();
  test::addTable(scene);
  test::addUr(scene, "mover", Pose::Identity());
  test::addUr(scene, "left", test::yawPose(0.9, 0.3, 0.0, M_PI));
  test::addUr(scene, "right", test::yawPose(-0.9, -0.3, 0.0));
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout layout = ObjectLayout::empty(scene);
  Rng rng(11);
  auto random_q = [&] {
    JointVector q = test::urHome();
    for (Eigen::Index i = 0; i < q.size(); ++i) q[i] += rng.uniform(-1.2, 1.2);
    return q;
  };
  int compared = 0, colliding = 0;
  for (int trial = 0; trial < 400 && compared < 120; ++trial) {
    const std::array<RobotState, 2> parked{RobotState{.robot = 1, .q = random_q()}, RobotState{.robot = 2, .q = random_q()}};
    if (robotsInCollision(world, context, parked, layout)) continue;  // parked robots stand free
    const RobotState start{.robot = 0, .q = random_q()};
    const JointVector end = random_q();
    const std::array<RobotMotion, 3> all{RobotMotion{start, end}, RobotMotion{parked[0], parked[0].q},
                                         RobotMotion{parked[1], parked[1].q}};
    const RobotMotion mover{start, end};
    const bool full = motionsInCollision(world, context, all, layout);
    const bool among = motionsAmongParked(world, context, std::span<const RobotMotion>(&mover, 1), parked, layout);
    EXPECT_EQ(full, among) << "trial " << trial;
    const bool state_full = robotsInCollision(world, context, std::array<RobotState, 3>{start, parked[0], parked[1]}, layout);
    const bool state_among = robotsAmongParked(world, context, std::span<const RobotState>(&start, 1), parked, layout);
    EXPECT_EQ(state_full, state_among) << "trial " << trial;
    ++compared;
    colliding += full ? 1 : 0;
  }
  EXPECT_GE(compared, 60);
  EXPECT_GT(colliding, 5);                // the mover meets the parked robots or the table...
  EXPECT_LT(colliding, compared - 5);     // ...and also passes them

  // A parked arm bent into the table: the full check fails every motion, the query among parked robots
  // only those that meet it.
  const RobotState sunk{.robot = 2, .q = test::joints({0, -0.2, 2.4, 0, 0, 0})};
  ASSERT_TRUE(robotInCollision(world, context, sunk, layout));
  const RobotMotion still{{.robot = 0, .q = test::urHome()}, test::urHome()};
  ASSERT_FALSE(robotInCollision(world, context, still.start, layout));
  EXPECT_TRUE(motionsInCollision(world, context, std::array<RobotMotion, 2>{still, RobotMotion{sunk, sunk.q}}, layout));
  EXPECT_FALSE(motionsAmongParked(world, context, std::span<const RobotMotion>(&still, 1),
                                  std::span<const RobotState>(&sunk, 1), layout));
}

}  // namespace
}  // namespace dash
