// `dashbench controller` as real child processes: a UR agent (with the simulated UR robot and gripper
// in this process) and a simulated arm run a 2-robot plan to success; a stop injected on the command
// line aborts both arms.
#include <gtest/gtest.h>

#include <cstdio>

#include "dispatch_test_util.h"

namespace dash::dispatch {
namespace {

using test::waitFor;

class ControllerCli : public ::testing::Test {
 protected:
  void SetUp() override {
    scene_ = test::multiArmScene(1);
    plan_ = test::multiArmPlan(scene_);
    DispatchConfig config;
    config.start_delay = 0.3;
    // Separate processes on a possibly loaded machine: tracking is not this test's subject.
    config.path_tolerance = ToleranceSpec{test::kLoadProofPathTolerance, {}};
    config.state_timeout = config.sample_timeout = test::kLoadProofStateTimeout;
    server_ = std::make_unique<test::TestServer>(config);
    token_file_ = test::writeTokenFile("dispatch_cli_token.txt");
  }
  void TearDown() override {
    sim_.reset();
    ur_.reset();
    server_.reset();
  }

  void startAgents(const std::vector<std::string>& sim_extra = {}) {
    ur_ = test::startCliUrArm(server_->url(), "ur5e_0", test::homeOf(scene_, "ur5e_0"), token_file_,
                              "dispatch_cli_ur.log");
    sim_ = test::startCliSimArm(server_->url(), "ur5e_1", test::homeOf(scene_, "ur5e_1"), token_file_,
                                "dispatch_cli_sim.log", sim_extra);
    ASSERT_TRUE(waitFor([&] { return test::controllersReady(server_->service(), {"ur5e_0", "ur5e_1"}); }, 20.0))
        << test::httpGet(server_->url(), "/api/controllers").body << "\nur agent log:\n" << ur_.agent->log()
        << "\nsim agent log:\n" << sim_->log();
  }

  Scene scene_;
  Plan plan_;
  std::unique_ptr<test::TestServer> server_;
  std::string token_file_;
  test::CliUrArm ur_;
  std::unique_ptr<test::ChildProcess> sim_;
};

TEST_F(ControllerCli, TwoRobotPlanSucceeds) {
  startAgents();
  const test::HttpReply reply = test::httpPost(server_->url(), "/api/dispatch", test::dispatchBody(plan_, scene_));
  ASSERT_EQ(reply.status, 202) << reply.body;
  const auto st = test::waitFinal(server_->service(), 15.0);
  ASSERT_TRUE(st && st->final);
  EXPECT_EQ(st->state, DispatchState::kSucceeded) << st->reason << "\n" << ur_.agent->log() << sim_->log();
  const RobotTrajectory& planned = *plan_.findRobot("ur5e_0");
  const auto received = ur_.robot->points();
  ASSERT_EQ(received.size(), planned.points.size() - 1);
  for (std::size_t i = 0; i < received.size(); ++i) {
    EXPECT_LT(maxAbsDifference(received[i].q, planned.points[i + 1].q), 1e-6) << "point " << i + 1;
    EXPECT_NEAR(received[i].duration, planned.points[i + 1].t - planned.points[i].t, 1e-6);
  }
  EXPECT_EQ(ur_.robot->programProblem(), "");
  EXPECT_FALSE(ur_.robot->halted()) << ur_.robot->haltReason();
  // Each agent's log says when its goal ended, and how (issue 41: it used to stop at "start in").
  EXPECT_NE(sim_->log().find(": succeeded after "), std::string::npos) << sim_->log();
  EXPECT_NE(ur_.agent->log().find(": succeeded after "), std::string::npos) << ur_.agent->log();
  EXPECT_EQ(sim_->stop(), 0) << sim_->log();
  // Ctrl-C / SIGTERM: the UR agent sends MODE_STOPPED before it closes its sockets.
  EXPECT_EQ(ur_.robot->stoppedByPcAt(), 0);
  EXPECT_EQ(ur_.agent->stop(), 0) << ur_.agent->log();
  EXPECT_TRUE(waitFor([&] { return ur_.robot->stoppedByPcAt() != 0; }, 5.0)) << "no MODE_STOPPED";
  EXPECT_FALSE(ur_.robot->halted()) << ur_.robot->haltReason();
}

TEST_F(ControllerCli, StopInjectedOnTheCommandLineAbortsBothArms) {
  startAgents({"--sim-stop-at", "0.3"});
  const std::string options = "{\"path_tolerance\": {\"all\": 0.5, \"wrist_3_joint\": 0.25}}";
  ASSERT_EQ(test::httpPost(server_->url(), "/api/dispatch", test::dispatchBody(plan_, scene_, options)).status, 202);
  const auto st = test::waitFinal(server_->service(), 15.0);
  ASSERT_TRUE(st && st->final);
  EXPECT_EQ(st->state, DispatchState::kAborted);
  EXPECT_NE(st->reason.find("ur5e_1 left its path: joint 5 (wrist_3_joint)"), std::string::npos) << st->reason;
  EXPECT_EQ(test::armStatus(*st, "ur5e_0")->result, ResultCode::kCancelled);
  EXPECT_FALSE(ur_.robot->cancelTimes().empty());
}

TEST(ControllerCliArgs, WrongTokenEndsTheAgentWithTwoSayingTheServerRefusedIt) {
  DispatchConfig config;
  test::TestServer server(config);
  const std::string wrong = test::writeTokenFile("dispatch_cli_wrong_token.txt", "not-the-server-token");
  test::ChildProcess agent(test::dashbenchCommand({"controller", "--server", server.url(), "--robot", "ur5e_1",
                                                  "--token-file", wrong, "--driver", "sim"}),
                           {.output = ::testing::TempDir() + "dispatch_cli_wrong_token.log"});
  const std::optional<int> status = agent.wait(10.0);
  EXPECT_EQ(status, std::optional<int>(2)) << agent.log();
  EXPECT_NE(agent.log().find("refused this agent's token (HTTP 401)"), std::string::npos) << agent.log();
}

TEST(ControllerCliArgs, BadArgumentsExitWithTwo) {
  const std::string token = test::writeTokenFile("dispatch_cli_args_token.txt");
  test::ChildProcess bad(test::dashbenchCommand({"controller", "--server", "http://127.0.0.1:9", "--robot", "r",
                                                "--token-file", token, "--driver", "teleport"}),
                         {.output = ::testing::TempDir() + "dispatch_cli_bad.log"});
  const std::optional<int> status = bad.wait(10.0);
  EXPECT_EQ(status, std::optional<int>(2)) << bad.log();
  EXPECT_NE(bad.log().find("--driver"), std::string::npos) << bad.log();
}

}  // namespace
}  // namespace dash::dispatch
