// Acceptance: a real 2-robot sorting plan (the scenario generator's scene, planned here by Lazy-DaSH
// with a fixed seed) executes to success with ur5e_0 on `dashbench controller --driver ur` (the
// simulated UR robot in this process) and ur5e_1 on `dashbench controller --driver sim`, and the
// points the simulated UR robot decoded from the wire are the plan's points for ur5e_0.
//
// A real sorting plan lasts about 30 s, so it is dispatched with time_scale < 1 (faster). The scale
// is the smallest the pre-flight speed check lets through (plus 2 %), derived from the same peak
// speeds the check computes; a faster scale is shown to be refused before anything moves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "dispatch_test_util.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash::dispatch {
namespace {

using test::waitFor;

constexpr const char* kUrRobot = "ur5e_0";
constexpr const char* kSimRobot = "ur5e_1";

std::string optionsJson(double time_scale) { return nlohmann::json{{"time_scale", time_scale}}.dump(); }

/// A failed check `name` of a pre-flight report (any robot), if there is one.
const nlohmann::json* failedCheck(const nlohmann::json& report, const std::string& name) {
  for (const auto& c : report["checks"]) {
    if (c["name"] == name && !c["passed"].get<bool>()) return &c;
  }
  return nullptr;
}

class SortingDispatch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(generateScenario("sorting", {{"robots", "2"}, {"objects", "2"}}, 1, test::library()));
    PlannerSettings settings;
    settings.seed = 1;
    settings.time_limit = 120;
    PlanResult result = makePlanner("lazy-dash")->solve(*scene_, settings, Deadline(settings.time_limit), nullptr);
    ASSERT_EQ(result.outcome, PlanOutcome::kSolved) << result.message;
    ASSERT_TRUE(result.plan.has_value());
    plan_ = new Plan(*result.plan);
  }
  static void TearDownTestSuite() {
    delete plan_;
    delete scene_;
    plan_ = nullptr;
    scene_ = nullptr;
  }

  void SetUp() override {
    ASSERT_NE(plan_, nullptr) << "planning failed";
    DispatchConfig config;
    config.start_delay = 0.3;
    config.state_timeout = config.sample_timeout = test::kLoadProofStateTimeout;
    db_path_ = ::testing::TempDir() + "dispatch-sorting.db";
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(db_path_ + suffix);
    server_ = std::make_unique<test::TestServer>(config, db_path_);
    token_file_ = test::writeTokenFile("dispatch_sorting_token.txt");
  }
  void TearDown() override {
    sim_.reset();
    ur_.reset();
    server_.reset();
  }

  const JointVector& start(const std::string& robot) const { return plan_->findRobot(robot)->points.front().q; }

  /// The smallest time scale at which every arm's curve stays within its velocity limits: the peak
  /// speed ratio at scale 1 (the curves' shape does not depend on the scale; speeds go as 1/scale).
  double smallestTimeScale() const {
    double ratio = 0.0;
    for (const RobotTrajectory& rt : plan_->robots) {
      const RobotModel& model = *scene_->robots[static_cast<std::size_t>(scene_->robotIndex(rt.robot))].model;
      ratio = std::max(ratio, peakSpeed(armTrajectoryFromPlan(*plan_, rt.robot, 1.0), model.limits.velocity_max).ratio);
    }
    return ratio;
  }

  // RealTwoRobotPlanRunsFasterToSuccessAndTheUrRobotGetsEveryPoint's steps.
  void expectTooFastIsRefused(double min_scale) {
    // Faster than the limits allow: refused by the pre-flight speed check, nothing moves.
    const std::string body_too_fast = test::dispatchBody(*plan_, *scene_, optionsJson(min_scale * 0.8));
    const test::HttpReply checked = test::httpPost(server_->url(), "/api/dispatch/preflight", body_too_fast);
    ASSERT_EQ(checked.status, 200) << checked.body;
    const auto too_fast = nlohmann::json::parse(checked.body);
    EXPECT_FALSE(too_fast["passed"].get<bool>());
    const nlohmann::json* speed = failedCheck(too_fast, "speed_limits");
    ASSERT_NE(speed, nullptr) << checked.body;
    EXPECT_NE((*speed)["message"].get<std::string>().find("time_scale >= "), std::string::npos) << speed->dump();
    EXPECT_EQ(failedCheck(too_fast, "plan_valid"), nullptr) << "only the speeds fail";
    const test::HttpReply refused = test::httpPost(server_->url(), "/api/dispatch", body_too_fast);
    EXPECT_EQ(refused.status, 422) << refused.body;
    EXPECT_TRUE(ur_.robot->commands().empty());
    EXPECT_TRUE(ur_.robot->points().empty());
  }
  void expectUrRobotGotEveryPoint(double scale) {
    // What the simulated UR robot decoded from the wire (int32 big-endian / 1e6) is the plan's points for
    // ur5e_0, each segment's duration scaled. The first point is where the arm stood (the pre-flight's
    // start_state check), so the driver does not send it.
    const RobotTrajectory& planned = *plan_->findRobot(kUrRobot);
    const auto received = ur_.robot->points();
    ASSERT_EQ(received.size(), planned.points.size() - 1);
    for (std::size_t i = 0; i < received.size(); ++i) {
      const TrajectoryPoint& p = planned.points[i + 1];
      for (int j = 0; j < 6; ++j) {
        const double decoded = received[i].raw[static_cast<std::size_t>(j)] / 1e6;
        EXPECT_NEAR(decoded, p.q[j], 1e-6) << "point " << i + 1 << " joint " << j;
      }
      EXPECT_NEAR(received[i].duration, (p.t - planned.points[i].t) * scale, 1e-6) << "point " << i + 1;
    }
    EXPECT_LT(maxAbsDifference(ur_.robot->q(), planned.points.back().q), 1e-6);
    EXPECT_EQ(ur_.robot->resultsSent(), std::vector<std::int32_t>{0});
    EXPECT_FALSE(ur_.robot->halted()) << ur_.robot->haltReason();
    EXPECT_EQ(ur_.robot->programProblem(), "");
  }
  void expectGripperInPlanOrder() {
    // ur5e_0's grasps and releases reached its gripper, in the plan's order.
    std::vector<std::string> expected_gripper;
    std::vector<const PlanEvent*> ur_events;
    for (const PlanEvent& e : plan_->events) {
      if (e.robot == kUrRobot && e.type != PlanEvent::Type::kInspect) ur_events.push_back(&e);
    }
    std::stable_sort(ur_events.begin(), ur_events.end(),
                     [](const PlanEvent* a, const PlanEvent* b) { return a->t < b->t; });
    for (const PlanEvent* e : ur_events)
      expected_gripper.push_back(e->type == PlanEvent::Type::kGrasp ? "SET POS 255 SPE 255 FOR 255 GTO 1"
                                                                    : "SET POS 0 SPE 255 FOR 255 GTO 1");
    std::vector<std::string> gripper;
    for (const auto& c : ur_.gripper->commands()) {
      if (c.line.rfind("SET POS", 0) == 0) gripper.push_back(c.line);
    }
    EXPECT_EQ(gripper, expected_gripper);
  }

  static Scene* scene_;
  static Plan* plan_;
  std::string db_path_;
  std::string token_file_;
  std::unique_ptr<test::TestServer> server_;
  test::CliUrArm ur_;
  std::unique_ptr<test::ChildProcess> sim_;
};

Scene* SortingDispatch::scene_ = nullptr;
Plan* SortingDispatch::plan_ = nullptr;

TEST_F(SortingDispatch, RealTwoRobotPlanRunsFasterToSuccessAndTheUrRobotGetsEveryPoint) {
  ASSERT_EQ(plan_->robots.size(), 2u);
  ASSERT_NE(plan_->findRobot(kUrRobot), nullptr);
  ASSERT_NE(plan_->findRobot(kSimRobot), nullptr);
  int ur_gripper_events = 0;
  for (const PlanEvent& e : plan_->events)
    ur_gripper_events += e.robot == kUrRobot && e.type != PlanEvent::Type::kInspect;
  ASSERT_GT(ur_gripper_events, 0) << "a sorting plan hands cubes over: both arms grasp";

  ur_ = test::startCliUrArm(server_->url(), kUrRobot, start(kUrRobot), token_file_, "dispatch_sorting_ur.log");
  sim_ = test::startCliSimArm(server_->url(), kSimRobot, start(kSimRobot), token_file_, "dispatch_sorting_sim.log");
  ASSERT_TRUE(waitFor(
      [&] {
        return test::controllersReady(server_->service(), {kUrRobot, kSimRobot});
      },
      20.0))
      << test::httpGet(server_->url(), "/api/controllers").body << "\nur agent log:\n"
      << ur_.agent->log() << "\nsim agent log:\n"
      << sim_->log();

  const double min_scale = smallestTimeScale();
  ASSERT_GT(min_scale, 0.0);
  const double scale = std::ceil(min_scale * 1.02 * 1000.0) / 1000.0;
  std::printf("[ measure  ] makespan %.2f s, peak speed %.1f%% of the limit: time_scale %.3f (%.2f s)\n",
              plan_->makespan, min_scale * 100.0, scale, plan_->makespan * scale);

  ASSERT_NO_FATAL_FAILURE(expectTooFastIsRefused(min_scale));

  // The smallest scale the limits allow: every check passes, and the plan runs to success.
  const test::HttpReply reply =
      test::httpPost(server_->url(), "/api/dispatch", test::dispatchBody(*plan_, *scene_, optionsJson(scale)));
  ASSERT_EQ(reply.status, 202) << reply.body;
  const auto accepted = nlohmann::json::parse(reply.body);
  EXPECT_TRUE(accepted["preflight"]["passed"].get<bool>());
  for (const auto& c : accepted["preflight"]["checks"]) EXPECT_TRUE(c["passed"].get<bool>()) << c.dump();

  const auto st = test::waitFinal(server_->service(), plan_->makespan * scale + 15.0);
  ASSERT_TRUE(st && st->final);
  EXPECT_EQ(st->state, DispatchState::kSucceeded) << st->reason << "\n" << ur_.agent->log() << sim_->log();
  EXPECT_DOUBLE_EQ(st->time_scale, scale);
  for (const ArmDispatchStatus& arm : st->arms) {
    EXPECT_EQ(arm.result, ResultCode::kSuccessful) << arm.robot << ": " << arm.message;
    std::printf("[ measure  ] %s: %d samples, max deviation %.4f rad\n", arm.robot.c_str(), arm.samples,
                arm.max_deviation);
  }

  ASSERT_NO_FATAL_FAILURE(expectUrRobotGotEveryPoint(scale));
  ASSERT_NO_FATAL_FAILURE(expectGripperInPlanOrder());

  // The simulated arm ended at its plan's last point.
  for (const ControllerInfo& c : server_->service().controllers()) {
    if (c.robot != kSimRobot) continue;
    ASSERT_TRUE(c.last_sample.has_value());
    EXPECT_LT(maxAbsDifference(c.last_sample->q, plan_->findRobot(kSimRobot)->points.back().q), 0.01);
  }

  // Recorded with its time scale; the refused request too.
  nlohmann::json history;
  waitFor(
      [&] {
        history = nlohmann::json::parse(test::httpGet(server_->url(), "/api/dispatches").body);
        return history["dispatches"].size() == 2 && history["dispatches"][0]["state"] == "succeeded";
      },
      3.0);
  ASSERT_EQ(history["dispatches"].size(), 2u) << history.dump();
  EXPECT_EQ(history["dispatches"][0]["state"], "succeeded");
  EXPECT_DOUBLE_EQ(history["dispatches"][0]["time_scale"].get<double>(), scale);
  EXPECT_EQ(history["dispatches"][1]["state"], "refused");

  EXPECT_EQ(sim_->stop(), 0) << sim_->log();
  EXPECT_EQ(ur_.agent->stop(), 0) << ur_.agent->log();
}

}  // namespace
}  // namespace dash::dispatch
