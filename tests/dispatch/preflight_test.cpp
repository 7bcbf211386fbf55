// Pre-flight checks, without any network: every refusal names its robot and reason.
#include <gtest/gtest.h>

#include "dispatch_test_util.h"
#include "server/dispatch/preflight.h"

namespace dash::dispatch {
namespace {

class Preflight : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = test::multiArmScene(1);
    plan_ = test::multiArmPlan(scene_);
    options_.now_us = 1'000'000'000;
    for (const SceneRobot& r : scene_.robots) {
      ControllerInfo c;
      c.robot = r.id;
      c.driver = "sim";
      c.joint_names = r.model->joint_names;
      c.connected = true;
      c.ready = true;
      c.last_sample = JointSample{options_.now_us, r.home, JointVector::Zero(6)};
      c.last_report_us = options_.now_us - 20'000;
      controllers_.push_back(c);
    }
  }
  const PreflightCheck* failed(const PreflightReport& report, const std::string& name) {
    for (const PreflightCheck& c : report.checks) {
      if (!c.passed && c.name == name) return &c;
    }
    return nullptr;
  }
  PreflightReport run() { return runPreflight(scene_, plan_, controllers_, options_); }

  Scene scene_;
  Plan plan_;
  std::vector<ControllerInfo> controllers_;
  PreflightOptions options_;
};

TEST_F(Preflight, PassesWithEveryArmAtItsStart) {
  const PreflightReport report = run();
  EXPECT_TRUE(report.passed) << report.reason();
  EXPECT_EQ(report.httpStatus(), 200);
  ASSERT_EQ(report.trajectories.size(), 2u);
  EXPECT_EQ(report.trajectories[0].robot, "ur5e_0");
  EXPECT_EQ(report.trajectories[0].gripper.size(), 2u);
}

TEST_F(Preflight, RefusesAnArmAwayFromTheStart) {
  controllers_[1].last_sample->q[2] += 0.2;
  const PreflightReport report = run();
  EXPECT_FALSE(report.passed);
  EXPECT_EQ(report.httpStatus(), 409);
  const PreflightCheck* c = failed(report, "start_state");
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->robot, "ur5e_1");
  EXPECT_NE(c->message.find("elbow_joint"), std::string::npos) << c->message;
  EXPECT_NE(report.reason().find("ur5e_1: the arm is not at the plan's start"), std::string::npos) << report.reason();
}

TEST_F(Preflight, RefusesAStaleState) {
  controllers_[0].last_report_us = options_.now_us - 2'000'000;
  const PreflightReport report = run();
  const PreflightCheck* c = failed(report, "start_state");
  ASSERT_NE(c, nullptr);
  EXPECT_NE(c->message.find("no recent joint state"), std::string::npos);
}

TEST_F(Preflight, RefusesAMissingOrBusyController) {
  controllers_.pop_back();
  PreflightReport report = run();
  const PreflightCheck* c = failed(report, "controller_connected");
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->robot, "ur5e_1");
  EXPECT_EQ(report.httpStatus(), 409);

  SetUp();
  controllers_[0].status = ArmStatus::kExecuting;
  EXPECT_NE(failed(run(), "controller_ready"), nullptr);
}

TEST_F(Preflight, RefusesJointNamesOutOfOrder) {
  std::swap(controllers_[1].joint_names[0], controllers_[1].joint_names[1]);
  const PreflightReport mismatch = run();
  const PreflightCheck* c = failed(mismatch, "joint_names");
  ASSERT_NE(c, nullptr);
  EXPECT_EQ(c->robot, "ur5e_1");

  SetUp();
  std::swap(plan_.robots[1].joint_names[4], plan_.robots[1].joint_names[5]);
  const PreflightReport report = run();
  EXPECT_NE(failed(report, "joint_names"), nullptr);
  EXPECT_EQ(report.httpStatus(), 422);
}

TEST_F(Preflight, RefusesTimesThatDoNotIncrease) {
  plan_.robots[1].points[2].t = plan_.robots[1].points[1].t;
  const PreflightReport report = run();
  const PreflightCheck* c = failed(report, "time_order");
  ASSERT_NE(c, nullptr);
  EXPECT_NE(c->message.find("point 2"), std::string::npos) << c->message;
  EXPECT_EQ(report.httpStatus(), 422);
}

TEST_F(Preflight, RefusesSpeedsBeyondTheLimitsAndSuggestsATimeScale) {
  // 0.6 rad in 0.24 s = 2.5 rad/s: within velocity_max (3.14) on the plan's lines, but easing into
  // and out of the corners needs 3.75 rad/s.
  plan_.robots[1].points[1].t = 0.24;
  const PreflightReport report = run();
  const PreflightCheck* c = failed(report, "speed_limits");
  ASSERT_NE(c, nullptr) << report.reason();
  EXPECT_NE(c->message.find("time_scale >= 1.19"), std::string::npos) << c->message;
  EXPECT_EQ(failed(report, "plan_valid"), nullptr) << report.reason();

  options_.time_scale = 1.25;
  EXPECT_EQ(failed(run(), "speed_limits"), nullptr);

  options_.time_scale = 1.0;
  plan_.robots[1].points[1].t = 0.15;  // 4 rad/s on the line itself
  EXPECT_NE(failed(run(), "speed_limits"), nullptr);
}

TEST_F(Preflight, RefusesAnInvalidPlan) {
  plan_.makespan = 9.0;
  const PreflightReport report = run();
  const PreflightCheck* c = failed(report, "plan_valid");
  ASSERT_NE(c, nullptr);
  EXPECT_NE(c->message.find("makespan"), std::string::npos) << c->message;
  EXPECT_EQ(report.httpStatus(), 422);
}

}  // namespace
}  // namespace dash::dispatch
