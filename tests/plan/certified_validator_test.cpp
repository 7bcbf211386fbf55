// The certified validator on hand-made plans that dip a set depth into something between two plan
// points (rejected, with the pair, the instant and the depth) or pass a set distance from it (valid).
#include <gtest/gtest.h>

#include "certified_test_scenes.h"
#include "engine/plan/plan_validator.h"

namespace dash {
namespace {

constexpr double kDip = 0.0002;       // m
constexpr double kFloor = 5e-5;       // m: the certificate's resolution (ValidationOptions::certify_floor)

const ValidationProblem* find(const ValidationReport& report, ProblemKind kind) {
  for (const ValidationProblem& p : report.problems) {
    if (p.kind == kind) return &p;
  }
  return nullptr;
}

TEST(CertifiedValidator, CubeCarriedPastAShelfEdgeIsRejected) {
  const Scene scene = test::shelfEdgeScene(kDip);
  const Plan plan = test::shelfEdgePlan(scene);
  const ValidationReport report = validatePlan(scene, plan);
  ASSERT_EQ(report.problems.size(), 1u) << report.summary();
  const ValidationProblem& p = report.problems[0];
  EXPECT_EQ(p.kind, ProblemKind::kHeldObjectCollision);
  EXPECT_EQ(p.object, "cube_0");
  EXPECT_EQ(p.other, "shelf");
  EXPECT_NEAR(p.distance, -kDip, kDip / 4.0) << p.message;  // contacts are followed in steps
  // The corner is deepest 0.1525 m into the 0.3 m diagonal that takes t = 6 to 7.
  EXPECT_NEAR(p.t_closest, 6.0 + 0.1525 / 0.3, 1e-3);
  EXPECT_LT(p.t, p.t_closest);
  EXPECT_GT(p.t_end, p.t_closest);
}

TEST(CertifiedValidator, TheSampledCheckMissesTheShelfEdge) {
  // Why the certificate: the 1 cm sampler looks 2.5 mm of travel either side of the 0.4 mm dip.
  const Scene scene = test::shelfEdgeScene(kDip);
  ValidationOptions sampled;
  sampled.geometry = ValidationOptions::GeometryCheck::kSampled;
  EXPECT_TRUE(validatePlan(scene, test::shelfEdgePlan(scene), sampled).valid());
}

TEST(CertifiedValidator, CubeCarriedClearOfTheShelfEdgePasses) {
  const Scene scene = test::shelfEdgeScene(-kDip);  // 0.2 mm outside in x and y: 0.28 mm away
  const Plan plan = test::shelfEdgePlan(scene);
  const ValidationReport report = validatePlan(scene, plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  EXPECT_NEAR(report.closest.distance, kDip * std::sqrt(2.0), kFloor);
  EXPECT_EQ(report.closest.b, "shelf");
  // A stricter margin, as for hardware, rejects it with the distance reached.
  ValidationOptions strict;
  strict.clearance = 0.001;
  const ValidationReport margin = validatePlan(scene, plan, strict);
  ASSERT_EQ(margin.problems.size(), 1u) << margin.summary();
  EXPECT_NEAR(margin.problems[0].distance, kDip * std::sqrt(2.0), kDip / 4.0);
}

TEST(CertifiedValidator, Resting_and_grasping_contacts_are_not_problems) {
  // The cube sits on the deck at its grasp and its release, and the tool touches its top face.
  const Scene scene = test::shelfEdgeScene(-0.05);
  const ValidationReport report = validatePlan(scene, test::shelfEdgePlan(scene));
  EXPECT_TRUE(report.valid()) << report.summary();
  bool allowed = false;
  for (const PairClearance& p : report.pairs) allowed = allowed || p.contact_allowed;
  EXPECT_TRUE(allowed);
}

TEST(CertifiedValidator, AGripperTouchingAnObjectItDoesNotGraspIsRejected) {
  // The tool may touch cube_0, which it grasps and releases, but not cube_1, which it only passes.
  const Scene scene = test::neighbourCubeScene();
  const ValidationReport report = validatePlan(scene, test::neighbourCubePlan(scene, kDip));
  ASSERT_EQ(report.problems.size(), 1u) << report.summary();
  const ValidationProblem& p = report.problems[0];
  EXPECT_EQ(p.kind, ProblemKind::kRobotObjectCollision) << p.message;
  EXPECT_EQ(p.robot, "gantry_0");
  EXPECT_EQ(p.other, "cube_1") << p.message;
  EXPECT_NEAR(p.distance, -kDip, kDip / 4.0) << p.message;
  EXPECT_NEAR(p.t_closest, 4.0, 1e-3);
}

TEST(CertifiedValidator, AGripperStoppingAboveAnObjectItDoesNotGraspPasses) {
  const Scene scene = test::neighbourCubeScene();
  const ValidationReport report = validatePlan(scene, test::neighbourCubePlan(scene, -kDip));
  EXPECT_TRUE(report.valid()) << report.summary();
  EXPECT_NEAR(report.closest.distance, kDip, kFloor);
  EXPECT_EQ(report.closest.b, "cube_1");
}

TEST(CertifiedValidator, AGripperMayTouchWhatItJustReleasedWhateverOtherRobotsDo) {
  // gantry_0 presses 0.2 mm into the cube it has just put down while gantry_1's grasp and release cut
  // that time into epochs of their own: still the object its hand last held, so contact is meant.
  const Scene scene = test::twoGantriesScene();
  const ValidationReport report = validatePlan(scene, test::pressAfterReleasePlan(scene, kDip));
  EXPECT_TRUE(report.valid()) << report.summary();
  // Without gantry_0's grasp and release the same press is a collision with cube_0: the allowance
  // comes from the release, not from the geometry.
  Plan never_held = test::pressAfterReleasePlan(scene, kDip);
  std::erase_if(never_held.events, [](const PlanEvent& e) { return e.robot == "gantry_0"; });
  const ValidationReport bad = validatePlan(scene, never_held);
  ASSERT_FALSE(bad.valid());
  EXPECT_EQ(bad.problems[0].kind, ProblemKind::kRobotObjectCollision) << bad.summary();
  EXPECT_EQ(bad.problems[0].other, "cube_0") << bad.summary();
  EXPECT_NEAR(bad.problems[0].distance, -kDip, kDip / 4.0) << bad.summary();
}

TEST(CertifiedValidator, HeldCubePushedIntoItsTableFromAboveIsRejected) {
  // Lowering the cube 2 mm below the deck top at the release: the bottom face's tolerance is 1 mm.
  const Scene scene = test::shelfEdgeScene(-0.05);
  Plan plan = test::shelfEdgePlan(scene);
  for (TrajectoryPoint& point : plan.robots[0].points) {
    if (point.t == 9.0) point.q[2] += 0.002;  // the TCP 2 mm lower
  }
  const ValidationReport report = validatePlan(scene, plan);
  const ValidationProblem* p = find(report, ProblemKind::kHeldObjectCollision);
  ASSERT_NE(p, nullptr) << report.summary();
  EXPECT_EQ(p->other, "deck");
}

TEST(CertifiedValidator, GrippersClosingTooFarAtAHandoverAreRejected) {
  const test::HandoverCase handover = test::urHandover(0.0003);
  ASSERT_NEAR(handover.reached, -0.0003, 1e-6);
  const ValidationReport report = validatePlan(handover.scene, handover.plan);
  const ValidationProblem* p = find(report, ProblemKind::kRobotRobotCollision);
  ASSERT_NE(p, nullptr) << report.summary();
  EXPECT_NEAR(p->distance, -0.0003, 0.0003 / 4.0) << p->message;
  EXPECT_NEAR(p->t_closest, 1.0, 0.2);
  for (const ValidationProblem& q : report.problems) EXPECT_EQ(q.kind, ProblemKind::kRobotRobotCollision) << q.message;
}

TEST(CertifiedValidator, GrippersStoppingShortAtAHandoverPass) {
  const test::HandoverCase handover = test::urHandover(-0.0003);
  ASSERT_NEAR(handover.reached, 0.0003, 1e-6);
  const ValidationReport report = validatePlan(handover.scene, handover.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  EXPECT_NEAR(report.closest.distance, 0.0003, kFloor);
}

TEST(CertifiedValidator, HostileOptionsAreRefused) {
  const Scene scene = test::shelfEdgeScene(-kDip);
  const Plan plan = test::shelfEdgePlan(scene);
  EXPECT_THROW(validatePlan(scene, plan, {.clearance = -0.001}), std::exception);
  EXPECT_THROW(validatePlan(scene, plan, {.clearance = 5.0}), std::exception);
  EXPECT_THROW(validatePlan(scene, plan, {.certify_floor = 0.0}), std::exception);
}

}  // namespace
}  // namespace dash

namespace dash {
namespace {

TEST(CertifiedValidator, ForearmGrazingAWallIsRejected) {
  const test::ForearmCase graze = test::forearmWall(kDip);
  ASSERT_NEAR(graze.reached, -kDip, 1e-5);
  const ValidationReport report = validatePlan(graze.scene, graze.plan);
  ASSERT_EQ(report.problems.size(), 1u) << report.summary();
  const ValidationProblem& p = report.problems[0];
  EXPECT_EQ(p.kind, ProblemKind::kRobotObstacleCollision);
  EXPECT_EQ(p.other, "wall");
  EXPECT_NE(p.message.find("forearm"), std::string::npos) << p.message;
  EXPECT_NEAR(p.distance, -kDip, kDip / 4.0) << p.message;
  EXPECT_GT(p.t, 0.0);
  EXPECT_LT(p.t_end, 1.0);
}

TEST(CertifiedValidator, TheSampledCheckSeesTheForearmToo) {
  // A capsule's curvature makes a 0.2 mm graze last about 9 mm of travel: the 1 cm sampler sees it,
  // and would see any such forearm graze (docs/validation.md: its instants are at most 6.7 mm of a
  // forearm point's travel apart). FingertipsCutAtAHandover... is a case the sampler misses.
  const test::ForearmCase graze = test::forearmWall(kDip);
  ValidationOptions sampled;
  sampled.geometry = ValidationOptions::GeometryCheck::kSampled;
  EXPECT_FALSE(validatePlan(graze.scene, graze.plan, sampled).valid());
}

TEST(CertifiedValidator, ForearmPassingAWallPasses) {
  const test::ForearmCase pass = test::forearmWall(-kDip);
  const ValidationReport report = validatePlan(pass.scene, pass.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  EXPECT_NEAR(report.closest.distance, kDip, kFloor);
  EXPECT_EQ(report.closest.b, "wall");
}

}  // namespace
}  // namespace dash
namespace dash {
namespace {

TEST(CertifiedValidator, APairNotCertifiedAtTheFloorIsAPossibleContact) {
  // The cube's corner passes the shelf's edge 2.8 um away: every measured instant is clear, but no
  // step of 0.05 mm of motion proves the pair apart around the closest instant.
  const Scene scene = test::shelfEdgeScene(-2e-6);
  const Plan plan = test::shelfEdgePlan(scene);
  const ValidationReport report = validatePlan(scene, plan);
  ASSERT_EQ(report.problems.size(), 1u) << report.summary();
  const ValidationProblem& p = report.problems[0];
  EXPECT_EQ(p.kind, ProblemKind::kHeldObjectCollision);
  EXPECT_EQ(p.object, "cube_0");
  EXPECT_EQ(p.other, "shelf");
  EXPECT_NE(p.message.find("may touch"), std::string::npos) << p.message;
  EXPECT_NE(p.message.find("not certified at the 0.05 mm floor"), std::string::npos) << p.message;
  EXPECT_GE(p.distance, 0.0) << p.message;  // the closest measured
  EXPECT_LT(p.distance, kFloor) << p.message;
  EXPECT_NEAR(p.t_closest, 6.0 + 0.1525 / 0.3, 1e-3);
  // A finer floor proves it apart.
  const ValidationReport finer = validatePlan(scene, plan, {.certify_floor = 1e-6});
  EXPECT_TRUE(finer.valid()) << finer.summary();
  EXPECT_NEAR(finer.closest.distance, 2e-6 * std::sqrt(2.0), 1e-6);
}

TEST(CertifiedValidator, AGripperTakingAnObjectOverMayTouchIt) {
  // The taker's fingers pass 0.8 mm from the plate the giver holds on their way to grasp it: contact
  // by design (as a gripper about to grasp a resting object), so neither the clearance nor the floor
  // rule applies to the pair (Handover.* in plan_validator_scenes_test.cpp: tools touching at 0).
  const test::HandoverCase handover = test::urHandover(-0.0003);
  const ValidationReport report = validatePlan(handover.scene, handover.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  bool meant = false;
  for (const PairClearance& p : report.pairs) meant = meant || (p.contact_allowed && p.a.find("held by") != std::string::npos);
  EXPECT_TRUE(meant);
}

}  // namespace
}  // namespace dash

namespace dash {
namespace {

TEST(CertifiedValidator, FingertipsCutAtAHandoverBetweenPlanPointsAreRejected) {
  // ur5e_1 comes in past the fingers that hold the plate; its fingertip cuts 0.3 mm into the corner
  // of ur5e_0's for 0.85 mm of travel, halfway between two of the sampler's instants (both plan
  // points and both those instants clear).
  const test::FingertipCase clip = test::urFingertipClip(0.0003);
  ASSERT_NEAR(clip.reached, -0.0003, 1e-6);
  EXPECT_GT(clip.at_samples, 0.0) << clip.sampler_steps;  // about 0.07 mm apart there
  const ValidationReport report = validatePlan(clip.scene, clip.plan);
  ASSERT_EQ(report.problems.size(), 1u) << report.summary();
  const ValidationProblem& p = report.problems[0];
  EXPECT_EQ(p.kind, ProblemKind::kRobotRobotCollision);
  EXPECT_EQ(p.robot, "ur5e_0");
  EXPECT_EQ(p.other, "ur5e_1");
  EXPECT_NE(p.message.find("robot ur5e_0 body finger_"), std::string::npos) << p.message;
  EXPECT_NE(p.message.find("robot ur5e_1 body finger_"), std::string::npos) << p.message;
  EXPECT_NEAR(p.distance, -0.0003, 0.0003 / 4.0) << p.message;
  EXPECT_NEAR(p.t_closest, 1.0 + clip.u_deepest, 1e-3) << p.message;
  EXPECT_GT(p.t, 1.0);
  EXPECT_LT(p.t_end, 2.0);
}

TEST(CertifiedValidator, TheSampledCheckMissesTheFingertips) {
  // Why the certificate: the sampler's 1 cm bound is about 1 mm of this fingertip's travel, and the
  // cut is shorter, halfway between two instants.
  const test::FingertipCase clip = test::urFingertipClip(0.0003);
  ValidationOptions sampled;
  sampled.geometry = ValidationOptions::GeometryCheck::kSampled;
  const ValidationReport report = validatePlan(clip.scene, clip.plan, sampled);
  EXPECT_TRUE(report.valid()) << report.summary();
}

TEST(CertifiedValidator, FingertipsPassingClearAtAHandoverPass) {
  const test::FingertipCase clear = test::urFingertipClip(-0.0003);
  ASSERT_NEAR(clear.reached, 0.0003, 1e-6);
  const ValidationReport report = validatePlan(clear.scene, clear.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  EXPECT_NEAR(report.closest.distance, 0.0003, kFloor);
}

}  // namespace
}  // namespace dash
