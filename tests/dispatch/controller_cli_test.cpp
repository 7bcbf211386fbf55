// `dashbench controller` as real child processes: a UR agent (with the simulated UR robot and gripper
// in this process) and a simulated arm run a 2-robot plan to success; a stop injected on the command
// line aborts both arms.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

#include "dispatch_test_util.h"

namespace dash::dispatch {
namespace {

using test::waitFor;

std::string csv(const JointVector& q) {
  std::ostringstream out;
  out.precision(17);
  for (Eigen::Index i = 0; i < q.size(); ++i) out << (i ? "," : "") << q[i];
  return out.str();
}

class ControllerCli : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = test::multiArmScene(1);
    plan_ = test::multiArmPlan(scene_);
    DispatchConfig config;
    config.start_delay = 0.3;
    server_ = std::make_unique<test::TestServer>(config);
    token_file_ = test::writeTokenFile("dispatch_cli_token.txt");
  }
  void TearDown() override {
    sim_.reset();
    ur_.reset();
    robot_.reset();
    gripper_.reset();
    server_.reset();
  }

  void startAgents(const std::vector<std::string>& sim_extra = {}) {
    gripper_ = std::make_unique<test::SimGripper>();
    const std::vector<int> ports = test::freePorts(4);  // reverse, script, trajectory, script command
    test::SimUrRobotOptions options;
    options.initial = test::homeOf(scene_, "ur5e_0");
    options.reverse_port = ports[0];
    options.script_port = ports[1];
    options.trajectory_port = ports[2];
    options.script_command_port = ports[3];
    robot_ = std::make_unique<test::SimUrRobot>(options);
    robot_->start();
    const std::vector<std::string> common = {"controller", "--server", server_->url(), "--token-file", token_file_};
    std::vector<std::string> ur_args = common;
    for (const std::string& a :
         {std::string("--robot"), std::string("ur5e_0"), std::string("--driver"), std::string("ur"),
          std::string("--robot-ip"), std::string("127.0.0.1"), std::string("--host-ip"), std::string("127.0.0.1"),
          std::string("--listen-host"), std::string("127.0.0.1"), std::string("--reverse-port"), std::to_string(ports[0]),
          std::string("--script-port"), std::to_string(ports[1]), std::string("--trajectory-port"),
          std::to_string(ports[2]), std::string("--script-command-port"), std::to_string(ports[3]),
          std::string("--rtde-port"), std::to_string(robot_->rtdePort()), std::string("--gripper"),
          std::string("robotiq"), std::string("--gripper-host"), std::string("127.0.0.1"), std::string("--gripper-port"),
          std::to_string(gripper_->port())}) {
      ur_args.push_back(a);
    }
    ur_ = std::make_unique<test::ChildProcess>(ur_args, ::testing::TempDir() + "dispatch_cli_ur.log");
    std::vector<std::string> sim_args = common;
    for (const std::string& a : {std::string("--robot"), std::string("ur5e_1"), std::string("--driver"),
                                 std::string("sim"), std::string("--sim-start"), csv(test::homeOf(scene_, "ur5e_1"))}) {
      sim_args.push_back(a);
    }
    sim_args.insert(sim_args.end(), sim_extra.begin(), sim_extra.end());
    sim_ = std::make_unique<test::ChildProcess>(sim_args, ::testing::TempDir() + "dispatch_cli_sim.log");
    ASSERT_TRUE(waitFor([&] { return test::controllersReady(server_->service(), {"ur5e_0", "ur5e_1"}); }, 20.0))
        << test::httpGet(server_->url(), "/api/controllers").body << "\nur agent log:\n" << ur_->log()
        << "\nsim agent log:\n" << sim_->log();
  }

  Scene scene_;
  Plan plan_;
  std::unique_ptr<test::TestServer> server_;
  std::string token_file_;
  std::unique_ptr<test::SimGripper> gripper_;
  std::unique_ptr<test::SimUrRobot> robot_;
  std::unique_ptr<test::ChildProcess> ur_, sim_;
};

TEST_F(ControllerCli, TwoRobotPlanSucceeds) {
  startAgents();
  const test::HttpReply reply = test::httpPost(server_->url(), "/api/dispatch", test::dispatchBody(plan_, scene_));
  ASSERT_EQ(reply.status, 202) << reply.body;
  const auto st = test::waitFinal(server_->service(), 15.0);
  ASSERT_TRUE(st && st->final);
  EXPECT_EQ(st->state, DispatchState::kSucceeded) << st->reason << "\n" << ur_->log() << sim_->log();
  const RobotTrajectory& planned = *plan_.findRobot("ur5e_0");
  const auto received = robot_->points();
  ASSERT_EQ(received.size(), planned.points.size() - 1);
  for (std::size_t i = 0; i < received.size(); ++i) {
    EXPECT_LT(maxAbsDifference(received[i].q, planned.points[i + 1].q), 1e-6) << "point " << i + 1;
    EXPECT_NEAR(received[i].duration, planned.points[i + 1].t - planned.points[i].t, 1e-6);
  }
  EXPECT_EQ(robot_->programProblem(), "");
  EXPECT_FALSE(robot_->halted()) << robot_->haltReason();
  EXPECT_EQ(sim_->stop(), 0) << sim_->log();
  EXPECT_EQ(ur_->stop(), 0) << ur_->log();
}

TEST_F(ControllerCli, StopInjectedOnTheCommandLineAbortsBothArms) {
  startAgents({"--sim-stop-at", "0.5"});
  ASSERT_EQ(test::httpPost(server_->url(), "/api/dispatch", test::dispatchBody(plan_, scene_)).status, 202);
  const auto st = test::waitFinal(server_->service(), 15.0);
  ASSERT_TRUE(st && st->final);
  EXPECT_EQ(st->state, DispatchState::kAborted);
  EXPECT_NE(st->reason.find("ur5e_1 deviated"), std::string::npos) << st->reason;
  EXPECT_EQ(test::armStatus(*st, "ur5e_0")->result, ResultCode::kCancelled);
  EXPECT_FALSE(robot_->cancelTimes().empty());
}

TEST(ControllerCliArgs, BadArgumentsExitWithTwo) {
  const std::string token = test::writeTokenFile("dispatch_cli_args_token.txt");
  test::ChildProcess bad({"controller", "--server", "http://127.0.0.1:9", "--robot", "r", "--token-file", token,
                          "--driver", "teleport"},
                         ::testing::TempDir() + "dispatch_cli_bad.log");
  const std::optional<int> status = bad.wait(10.0);
  EXPECT_EQ(status, std::optional<int>(2)) << bad.log();
  EXPECT_NE(bad.log().find("--driver"), std::string::npos) << bad.log();
}

}  // namespace
}  // namespace dash::dispatch
