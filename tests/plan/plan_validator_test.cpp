// The validator on the contract's worked example and on variants of it that must be rejected.
#include <gtest/gtest.h>

#include "engine/plan/plan_validator.h"
#include "plan_test_util.h"

namespace dash {
namespace {

class ExamplePlan : public ::testing::Test {
 protected:
  ValidationReport check() const { return validatePlan(scene_, plan_, options_); }

  /// Expects the report to hold a problem of `kind`, and prints it on failure.
  static void expectKind(const ValidationReport& report, ProblemKind kind) {
    EXPECT_TRUE(report.has(kind)) << "expected " << problemKindName(kind) << ", got:\n" << report.summary();
  }

  Scene scene_ = test::exampleScene();
  Plan plan_ = test::examplePlan();
  ValidationOptions options_;
};

TEST_F(ExamplePlan, Validates) {
  const ValidationReport report = check();
  EXPECT_TRUE(report.valid()) << report.summary();
  // 1 cm resolution over a 3.38 s pick and place takes hundreds of samples.
  EXPECT_GT(report.samples, 100u);
}

TEST_F(ExamplePlan, ValidatesWithOneThreadToo) {
  options_.threads = 1;
  EXPECT_TRUE(check().valid());
}

TEST_F(ExamplePlan, RejectsReleaseInMidAir) {
  // Release 6 cm above the place pose (point 7, t = 2.38, is the pre-place pose), and go down empty.
  plan_.events[1].t = 2.18;
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kReleaseUnstable);
  expectKind(report, ProblemKind::kGoalNotReached);
}

TEST_F(ExamplePlan, RejectsGoalNotReached) {
  scene_.objects[0].X_WO_goal->translation().x() += 0.05;
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kGoalNotReached);
  EXPECT_EQ(report.problems.size(), 1u) << report.summary();
  EXPECT_EQ(report.problems[0].object, "obj_0");
}

TEST_F(ExamplePlan, RejectsGoalNotReachedWithoutTheEvents) {
  plan_.events.clear();
  plan_.makespan = 3.38;
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kGoalNotReached);
}

TEST_F(ExamplePlan, RejectsJointSpeedOverTheLimit) {
  plan_.robots[0].points[1].t = 0.2;  // 0.9 rad of elbow in 0.2 s is far beyond 3.14 rad/s... and more
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kVelocity);
  EXPECT_EQ(report.count(ProblemKind::kVelocity), 1);
  EXPECT_EQ(report.problems[0].robot, "ur5e_0");
}

TEST_F(ExamplePlan, ToleratesSpeedWithinTolerance) {
  // Shrink the first segment to exactly the fastest joint's limit: valid.
  auto& points = plan_.robots[0].points;
  const JointVector dq = (points[1].q - points[0].q).cwiseAbs();
  const auto& v_max = scene_.robots[0].model->limits.velocity_max;
  const double fastest = dq.cwiseQuotient(v_max).maxCoeff();
  EXPECT_LT(fastest, 1.09);
  const double shift = 1.09 - fastest;
  for (std::size_t k = 1; k < points.size(); ++k) points[k].t -= shift;
  for (auto& e : plan_.events) e.t -= shift;
  plan_.makespan -= shift;
  const ValidationReport report = check();
  EXPECT_FALSE(report.has(ProblemKind::kVelocity)) << report.summary();
  EXPECT_TRUE(report.valid()) << report.summary();
}

TEST_F(ExamplePlan, RejectsTimesNotIncreasing) {
  plan_.robots[0].points[3].t = plan_.robots[0].points[2].t;
  expectKind(check(), ProblemKind::kTimeOrder);
}

TEST_F(ExamplePlan, RejectsWrongJointNames) {
  std::swap(plan_.robots[0].joint_names[1], plan_.robots[0].joint_names[2]);
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kJointNames);
  EXPECT_EQ(report.count(ProblemKind::kJointNames), 1);
}

TEST_F(ExamplePlan, RejectsStartNotAtHome) {
  plan_.robots[0].points[0].q[0] += 0.01;
  expectKind(check(), ProblemKind::kStartHome);
}

TEST_F(ExamplePlan, RejectsStartAfterTimeZero) {
  plan_.robots[0].points[0].t = 0.05;
  expectKind(check(), ProblemKind::kStartTime);
}

TEST_F(ExamplePlan, RejectsEndAwayFromHome) {
  plan_.robots[0].points.pop_back();
  plan_.makespan = plan_.robots[0].points.back().t;
  expectKind(check(), ProblemKind::kEndHome);
  scene_.end_at_home = false;
  EXPECT_FALSE(check().has(ProblemKind::kEndHome));
}

TEST_F(ExamplePlan, RejectsJointOutsideItsLimits) {
  plan_.robots[0].points[1].q[2] = 3.2;  // elbow limit is pi
  expectKind(check(), ProblemKind::kJointLimit);
}

TEST_F(ExamplePlan, RejectsGraspWithWrongXTO) {
  plan_.events[0].X_TO.translation().x() += 0.02;
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kGraspPose);
  EXPECT_EQ(report.problems.front().kind, ProblemKind::kGraspPose);
  EXPECT_DOUBLE_EQ(report.problems.front().t, 1.39);
}

TEST_F(ExamplePlan, RejectsGraspTooFarFromTheObject) {
  plan_.events[0].t = 1.09;  // at the pre-grasp pose, 10 cm above the cube
  expectKind(check(), ProblemKind::kGraspPose);
}

TEST_F(ExamplePlan, RejectsReleaseOfAnObjectNotHeld) {
  plan_.events.erase(plan_.events.begin());
  expectKind(check(), ProblemKind::kReleaseNotHeld);
}

TEST_F(ExamplePlan, RejectsObjectStillHeldAtTheEnd) {
  plan_.events.pop_back();
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kHeldAtEnd);
}

TEST_F(ExamplePlan, RejectsGraspWithoutCapability) {
  scene_.robots[0].capabilities.clear();
  expectKind(check(), ProblemKind::kCapability);
}

TEST_F(ExamplePlan, RejectsGraspOfAFixedObject) {
  scene_.objects[0].fixed = true;
  expectKind(check(), ProblemKind::kFixedObject);
}

TEST_F(ExamplePlan, RejectsUnknownNames) {
  plan_.events[0].object = "obj_9";
  expectKind(check(), ProblemKind::kEventReference);
}

TEST_F(ExamplePlan, RejectsHeaderMistakes) {
  plan_.status = "failed";
  plan_.scene = "another-scene";
  plan_.makespan = 4.0;
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kStatus);
  expectKind(report, ProblemKind::kSceneName);
  expectKind(report, ProblemKind::kMakespan);
}

TEST_F(ExamplePlan, RejectsMissingAndUnknownRobots) {
  plan_.robots[0].robot = "ur5e_7";
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kRobotMissing);
  expectKind(report, ProblemKind::kRobotUnknown);
}

TEST_F(ExamplePlan, RejectsACubeTakenThroughTheTable) {
  // Lower the carrying poses by 5 cm: the held cube sinks into the table on the way.
  auto& points = plan_.robots[0].points;
  const RobotModel& model = *scene_.robots[0].model;
  for (std::size_t k : {5u, 6u}) {
    const Pose X_WT = forwardKinematics(model, scene_.robots[0].X_WB, points[k].q).X_WT;
    const Pose lower = Eigen::Translation3d(0.0, 0.0, -0.11) * X_WT;
    const auto solutions = inverseKinematics(model, scene_.robots[0].X_WB, lower);
    ASSERT_FALSE(solutions.empty());
    // The solution nearest the original keeps the motion short.
    auto nearest = solutions.front();
    for (const auto& q : solutions) {
      if ((q - points[k].q).norm() < (nearest - points[k].q).norm()) nearest = q;
    }
    points[k].q = nearest;
  }
  const ValidationReport report = check();
  expectKind(report, ProblemKind::kHeldObjectCollision);
}

TEST_F(ExamplePlan, MalformedPlansBuiltInCodeAreProblemsNotExceptions) {
  plan_.events[0].t = -1.0;
  plan_.robots[0].points[0].t = -0.5;
  ValidationReport report;
  EXPECT_NO_THROW(report = check());
  expectKind(report, ProblemKind::kTimeOrder);
  expectKind(report, ProblemKind::kStartTime);

  plan_ = test::examplePlan();
  plan_.robots[0].joint_names.pop_back();
  for (auto& p : plan_.robots[0].points) p.q.conservativeResize(5);
  EXPECT_NO_THROW(report = check());
  expectKind(report, ProblemKind::kJointNames);

  plan_ = test::examplePlan();
  plan_.robots[0].points.clear();
  EXPECT_NO_THROW(report = check());
  expectKind(report, ProblemKind::kStartTime);
}

TEST(ValidationReport, SummaryAndCounts) {
  ValidationReport report;
  EXPECT_TRUE(report.valid());
  report.problems.push_back({ProblemKind::kVelocity, 1.5, 1.5, "r", "", "", "too fast"});
  EXPECT_FALSE(report.valid());
  EXPECT_TRUE(report.has(ProblemKind::kVelocity));
  EXPECT_EQ(report.count(ProblemKind::kGoalNotReached), 0);
  EXPECT_EQ(report.summary(), "t=1.5 velocity r: too fast\n");
  EXPECT_STREQ(problemKindName(ProblemKind::kRobotRobotCollision), "robot_robot_collision");
}

}  // namespace
}  // namespace dash
