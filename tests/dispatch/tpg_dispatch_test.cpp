// Acceptance of issue 39: a real 2-robot sorting plan with handovers (the scenario generator's scene,
// planned here by Lazy-DaSH with a fixed seed) dispatched to ur5e_0 on `dashbench controller --driver
// ur` (the simulated UR robot in this process, its speed slider at 0.7, its gripper closing on a part
// in 1 s) and ur5e_1 on `dashbench controller --driver sim` (its gripper 1 s +- 0.2 s).
//  - "timed": the slowed arm leaves its path tolerance and every arm is stopped (aborted, no collision);
//  - "tpg": it completes with no fault; at every handover the receiver grasps at its handover
//    configuration while the giver holds still at its own, and the giver releases only after; the
//    executed timetable of the graph's nodes passes the certified validator; the record keeps the
//    executed times per segment.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "dispatch_test_util.h"
#include "engine/plan/plan_validator.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/tpg/tpg.h"
#include "engine/tpg/tpg_replay.h"

namespace dash::dispatch {
namespace {

using test::waitFor;

constexpr const char* kUrRobot = "ur5e_0";
constexpr const char* kSimRobot = "ur5e_1";
constexpr double kTimeScale = 0.8;  ///< segments ease in and out: peak 0.94 of the limits here

class TpgDispatch : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(generateScenario("sorting", {{"robots", "2"}, {"objects", "2"}}, 1, test::library()));
    PlannerSettings settings;
    settings.seed = 1;
    settings.time_limit = 120;
    PlanResult result = makePlanner("lazy-dash")->solve(*scene_, settings, Deadline(settings.time_limit), nullptr);
    ASSERT_EQ(result.outcome, PlanOutcome::kSolved) << result.message;
    plan_ = new Plan(*result.plan);
    graph_ = new tpg::Graph(tpg::buildGraph(*scene_, *plan_));
  }
  static void TearDownTestSuite() {
    delete graph_;
    delete plan_;
    delete scene_;
  }

  void SetUp() override {
    ASSERT_NE(plan_, nullptr) << "planning failed";
    DispatchConfig config;
    config.start_delay = 0.3;
    config.state_timeout = config.sample_timeout = test::kLoadProofStateTimeout;
    db_path_ = ::testing::TempDir() + "dispatch-tpg.db";
    for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(db_path_ + suffix);
    server_ = std::make_unique<test::TestServer>(config, db_path_);
    token_file_ = test::writeTokenFile("dispatch_tpg_token.txt");
    test::UrArmSetup setup;
    setup.robot.speed_scaling = 0.7;
    setup.gripper.stroke_time = 1.0 * 255.0 / setup.gripper.object_position;  // closes on the part in 1 s
    ur_ = test::startCliUrArm(server_->url(), kUrRobot, start(kUrRobot), token_file_, "dispatch_tpg_ur.log", setup);
    sim_ = test::startCliSimArm(server_->url(), kSimRobot, start(kSimRobot), token_file_, "dispatch_tpg_sim.log",
                                {"--sim-gripper-time", "1.0", "--sim-gripper-jitter", "0.2"});
    ASSERT_TRUE(waitFor([&] { return test::controllersReady(server_->service(), {kUrRobot, kSimRobot}); }, 20.0))
        << ur_.agent->log() << sim_->log();
  }
  void TearDown() override {
    sim_.reset();
    ur_.reset();
    server_.reset();
  }

  const JointVector& start(const std::string& robot) const { return plan_->findRobot(robot)->points.front().q; }
  std::string body(const std::string& execution) const {
    return test::dispatchBody(*plan_, *scene_,
                              nlohmann::json{{"time_scale", kTimeScale}, {"execution", execution}}.dump());
  }

  // ByDependenciesTheSlowedArmCompletesHandoversInPlaceAndTheExecutionIsValid's checks, given the
  // executed segments per robot, per graph node.
  int expectHandoversInPlace(std::map<std::string, std::map<int, SegmentRecord>>& records) {
    int handovers = 0;
    // Handovers: the receiver grasps at its handover configuration, the giver stands still at its own
    // until then, and releases only after the grasp is done (the gripper closed).
    for (const tpg::Edge& e : graph_->edges) {
      if (e.why != tpg::Edge::Why::kHandover) continue;
      const tpg::Node& to = graph_->nodes[static_cast<std::size_t>(e.to)];
      if (to.kind != tpg::Node::Kind::kEvent || plan_->events[static_cast<std::size_t>(to.event)].type != PlanEvent::Type::kGrasp) {
        continue;
      }
      const PlanEvent& grasp = plan_->events[static_cast<std::size_t>(to.event)];
      const std::string giver = graph_->robots[static_cast<std::size_t>(graph_->nodes[static_cast<std::size_t>(e.from)].robot)];
      ++handovers;
      const SegmentRecord& g = records[grasp.robot][e.to];
      EXPECT_LT(maxAbsDifference(g.q_start, plan_->findRobot(grasp.robot)->positionAt(grasp.t)), 0.01) << grasp.object;
      EXPECT_LT(maxAbsDifference(g.q_end, plan_->findRobot(grasp.robot)->positionAt(grasp.t)), 0.01) << grasp.object;
      const SegmentRecord& arrived = records[giver][e.from];
      EXPECT_LE(arrived.end, g.start + 1e-9);
      EXPECT_LT(maxAbsDifference(arrived.q_end, plan_->findRobot(giver)->positionAt(grasp.t)), 0.01) << grasp.object;
      for (const auto& [node, r] : records[giver]) {  // no motion of the giver while the receiver grasps
        if (r.kind != "motion") continue;
        EXPECT_TRUE(r.end <= g.start + 1e-9 || r.start >= g.end - 1e-9) << giver << " moved during the grasp of " << grasp.object;
      }
      for (const auto& [node, r] : records[giver]) {
        const tpg::Node& n = graph_->nodes[static_cast<std::size_t>(node)];
        if (n.kind != tpg::Node::Kind::kEvent) continue;
        const PlanEvent& ev = plan_->events[static_cast<std::size_t>(n.event)];
        if (ev.type == PlanEvent::Type::kRelease && ev.object == grasp.object && ev.t >= grasp.t - 1e-6) {
          EXPECT_GE(r.start, g.end - 1e-9) << giver << " released " << ev.object << " before the grasp was done";
        }
      }
    }
    return handovers;
  }
  void expectRecordedSegments(const DispatchStatus& st) {
    // The results database keeps how it ran and every step's planned and executed times.
    ASSERT_NE(server_->recorder(), nullptr);
    // The record is written as the dispatch starts and again just after its end: wait for the end's.
    ASSERT_TRUE(waitFor(
        [&] {
          const std::string json = server_->recorder()->recordJson(st.id);
          return !json.empty() && nlohmann::json::parse(json).value("state", "") != "running";
        },
        10.0));
    const auto record = nlohmann::json::parse(server_->recorder()->recordJson(st.id));
    EXPECT_EQ(record["execution"], "tpg");
    EXPECT_EQ(record["state"], "succeeded");
    for (const auto& arm : record["arms"]) {
      ASSERT_TRUE(arm["segments"].is_array()) << arm.dump();
      const ArmDispatchStatus* live = test::armStatus(st, arm["robot"].get<std::string>());
      ASSERT_NE(live, nullptr);
      ASSERT_EQ(arm["segments"].size(), live->segments.size());
      for (std::size_t k = 0; k < live->segments.size(); ++k) {
        EXPECT_NEAR(arm["segments"][k]["executed"][1].get<double>(), live->segments[k].end, 1e-9);
        EXPECT_NEAR(arm["segments"][k]["planned"][1].get<double>(), live->segments[k].planned_end, 1e-9);
      }
    }
  }

  static Scene* scene_;
  static Plan* plan_;
  static tpg::Graph* graph_;
  std::string db_path_;
  std::string token_file_;
  std::unique_ptr<test::TestServer> server_;
  test::CliUrArm ur_;
  std::unique_ptr<test::ChildProcess> sim_;
};

Scene* TpgDispatch::scene_ = nullptr;
Plan* TpgDispatch::plan_ = nullptr;
tpg::Graph* TpgDispatch::graph_ = nullptr;

TEST_F(TpgDispatch, TimedExecutionOfASlowedArmIsAbortedOnItsPath) {
  const test::HttpReply reply = test::httpPost(server_->url(), "/api/dispatch", body("timed"));
  ASSERT_EQ(reply.status, 202) << reply.body;
  const auto st = test::waitFinal(server_->service(), plan_->makespan * kTimeScale + 20.0);
  ASSERT_TRUE(st && st->final);
  EXPECT_EQ(st->state, DispatchState::kAborted) << st->reason;
  EXPECT_NE(st->reason.find(std::string(kUrRobot) + " left its path"), std::string::npos) << st->reason;
  std::printf("[ measure  ] timed: aborted after %.2f s of %.2f s planned: %s\n", st->elapsed, st->duration,
              st->reason.c_str());
}

// A graph that does not keep the arms apart never reaches them: the plan with a graph stripped of
// every edge between arms (handover and swept) is refused at pre-flight, its delayed replays failing
// the certified validator.
TEST_F(TpgDispatch, AGraphWhoseDelayedReplaysCollideIsRefusedAtPreflight) {
  tpg::Graph stripped = *graph_;
  std::erase_if(stripped.edges, [&](const tpg::Edge& e) {
    return stripped.nodes[static_cast<std::size_t>(e.from)].robot != stripped.nodes[static_cast<std::size_t>(e.to)].robot;
  });
  Plan plan = *plan_;
  plan.tpg = tpg::tpgToJson(stripped, plan);
  const std::string request = test::dispatchBody(plan, *scene_,
                                                 nlohmann::json{{"time_scale", kTimeScale}, {"execution", "tpg"}}.dump());
  const test::HttpReply reply = test::httpPost(server_->url(), "/api/dispatch/preflight", request);
  EXPECT_NE(reply.body.find("replays with random delays that respect the temporal plan graph fail"), std::string::npos)
      << reply.status << " " << reply.body.substr(0, 600);
  EXPECT_EQ(nlohmann::json::parse(reply.body, nullptr, false).value("passed", true), false) << reply.body.substr(0, 600);
  // The graph as built passes the same check.
  const test::HttpReply whole = test::httpPost(server_->url(), "/api/dispatch/preflight", body("tpg"));
  EXPECT_NE(whole.body.find("delayed replays certified"), std::string::npos) << whole.status << " " << whole.body.substr(0, 600);
}

/// Per arm: node -> its executed segment.
std::map<int, SegmentRecord> byNode(const ArmDispatchStatus& arm) {
  std::map<int, SegmentRecord> out;
  for (const SegmentRecord& r : arm.segments) out[r.node] = r;
  return out;
}

TEST_F(TpgDispatch, ByDependenciesTheSlowedArmCompletesHandoversInPlaceAndTheExecutionIsValid) {
  const test::HttpReply reply = test::httpPost(server_->url(), "/api/dispatch", body("tpg"));
  ASSERT_EQ(reply.status, 202) << reply.body;
  const auto st = test::waitFinal(server_->service(), plan_->makespan * kTimeScale * 3 + 30.0);
  ASSERT_TRUE(st && st->final);
  ASSERT_EQ(st->state, DispatchState::kSucceeded) << st->reason << "\n" << ur_.agent->log() << sim_->log();
  EXPECT_EQ(st->execution, "tpg");
  for (const ArmDispatchStatus& arm : st->arms) EXPECT_EQ(arm.result, ResultCode::kSuccessful) << arm.message;
  std::printf("[ measure  ] tpg: executed %.2f s, planned %.2f s (time_scale %.2f)\n", st->elapsed, st->duration,
              kTimeScale);

  // Every node ran, in the server's graph (the same as the one built here: deterministic).
  std::vector<double> start(graph_->nodes.size(), -1.0), end(graph_->nodes.size(), -1.0);
  std::map<std::string, std::map<int, SegmentRecord>> records;
  for (const ArmDispatchStatus& arm : st->arms) {
    records[arm.robot] = byNode(arm);
    for (const SegmentRecord& r : arm.segments) {
      ASSERT_GE(r.start, 0.0) << arm.robot << " node " << r.node;
      ASSERT_GE(r.end, r.start) << arm.robot << " node " << r.node;
      start[static_cast<std::size_t>(r.node)] = r.start;
      end[static_cast<std::size_t>(r.node)] = r.end;
    }
  }
  for (std::size_t i = 0; i < start.size(); ++i) ASSERT_GE(start[i], 0.0) << "node " << i << " never ran";

  EXPECT_GT(expectHandoversInPlace(records), 0);

  ASSERT_NO_FATAL_FAILURE(expectRecordedSegments(*st));

  // The executed timetable of the graph's nodes, replayed on the plan's paths: certified valid.
  tpg::Timing timing{start, end};
  const Plan executed = tpg::replayPlan(*plan_, *graph_, timing);
  const ValidationReport v = validatePlan(*scene_, executed);
  EXPECT_TRUE(v.valid()) << v.summary();
}

}  // namespace
}  // namespace dash::dispatch
