// The temporal plan graph of a real plan (engine/tpg): a 2-robot sorting plan with handovers, planned
// here by Lazy-DaSH with a fixed seed. Replays that respect the graph pass the certified validator;
// the graph without one of its edges lets some delay draw collide or break a handover.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scene/scene_json.h"
#include "engine/tpg/tpg.h"
#include "engine/tpg/tpg_replay.h"
#include "tests/tpg/tpg_test_util.h"

namespace dash::tpg {
namespace {

class SortingTpg : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    library_ = RobotLibrary::loadDefault();
    case_ = new Case(planAndBuild(library_, "2", "2"));
    scene_ = case_->scene.get();
    plan_ = case_->plan.get();
    graph_ = case_->graph.get();
  }
  static void TearDownTestSuite() { delete case_; }
  void SetUp() override { ASSERT_NE(graph_, nullptr) << "planning failed"; }

  static int count(Edge::Why why) { return countEdges(*graph_, why); }

  static std::shared_ptr<const RobotLibrary> library_;
  static Case* case_;
  static Scene* scene_;
  static Plan* plan_;
  static Graph* graph_;
};

std::shared_ptr<const RobotLibrary> SortingTpg::library_;
Case* SortingTpg::case_ = nullptr;
Scene* SortingTpg::scene_ = nullptr;
Plan* SortingTpg::plan_ = nullptr;
Graph* SortingTpg::graph_ = nullptr;

TEST_F(SortingTpg, GraphCoversEveryArmAndEventWithoutCycleAndHasHandoverEdges) {
  EXPECT_EQ(graphProblem(*graph_, *plan_), "");
  EXPECT_EQ(graph_->forced, 0);
  int handovers = 0;
  for (std::size_t i = 0; i < plan_->events.size(); ++i) {
    for (std::size_t j = 0; j < plan_->events.size(); ++j) {
      const PlanEvent& g = plan_->events[i];
      const PlanEvent& r = plan_->events[j];
      handovers += g.type == PlanEvent::Type::kGrasp && r.type == PlanEvent::Type::kRelease && g.object == r.object &&
                   g.robot != r.robot && g.t <= r.t + 1e-6 && g.t >= r.t - 5.0;
    }
  }
  ASSERT_GT(handovers, 0) << "the sorting plan hands a cube over";
  EXPECT_GE(count(Edge::Why::kHandover), 2 * handovers);
  EXPECT_GT(count(Edge::Why::kSwept) + count(Edge::Why::kObject), 0);
  std::printf("[ measure  ] %zu nodes, %zu edges (handover %d, object %d, swept %d), makespan %.2f s\n",
              graph_->nodes.size(), graph_->edges.size(), count(Edge::Why::kHandover), count(Edge::Why::kObject),
              count(Edge::Why::kSwept), plan_->makespan);
}

TEST_F(SortingTpg, UndelayedReplayIsThePlanItselfUpToItsCuts) {
  const Timing timing = schedule(*graph_, std::vector<double>(graph_->nodes.size(), 0.0),
                                 std::vector<double>(graph_->nodes.size(), 1.0));
  // Every edge goes forward in the plan's time, so nothing waits: each node starts when planned.
  for (std::size_t i = 0; i < graph_->nodes.size(); ++i) EXPECT_NEAR(timing.start[i], graph_->nodes[i].t0, 1e-9) << i;
  EXPECT_NEAR(timing.makespan(), plan_->makespan, 1e-9);
}

TEST_F(SortingTpg, HundredRandomDelayDrawsThatRespectTheGraphPassTheCertifiedValidator) {
  ReplayOptions options;
  options.draws = 100;
  options.max_wait = 3.0;
  options.max_stretch = 3.0;
  const ReplayReport r = checkReplays(*scene_, *plan_, *graph_, options);
  EXPECT_EQ(r.failed, 0) << "draw " << r.first_failed_draw << ": " << r.first_problem;
  EXPECT_EQ(r.draws, 100);
  EXPECT_GT(r.max_makespan, r.planned_makespan);
  std::printf("[ measure  ] makespan planned %.2f s, replays %.2f .. %.2f s\n", r.planned_makespan, r.min_makespan,
              r.max_makespan);
}

TEST_F(SortingTpg, WithoutOneOfItsEdgesSomeDelayDrawFailsTheValidator) {
  int needed = 0;
  std::string example;
  for (std::size_t k = 0; k < graph_->edges.size(); ++k) {
    ReplayOptions options;
    options.draws = 12;  // aimed at the edge's source: enough to show most needed edges, ~1 s each
    options.max_wait = 10.0;
    options.max_stretch = 6.0;
    options.wait_probability = 0.8;
    options.focus = graph_->edges[k].from;
    const ReplayReport r = checkReplays(*scene_, *plan_, withoutEdge(*graph_, k), options);
    if (r.failed > 0) {
      ++needed;
      if (example.empty()) example = std::string(edgeWhyName(graph_->edges[k].why)) + " edge " + std::to_string(k) + ": " + r.first_problem;
    }
  }
  std::printf("[ measure  ] %d of %zu edges are needed by some draw; e.g. %s\n", needed, graph_->edges.size(),
              example.c_str());
  EXPECT_GT(needed, 0);
}

TEST_F(SortingTpg, PlanFieldRoundTripsAndPlansWithoutItStayWithout) {
  Plan with = *plan_;
  with.tpg = tpgToJson(*graph_, *plan_);
  const Plan parsed = parsePlan(planToJson(with), "with.json");
  ASSERT_FALSE(parsed.tpg.empty());
  const Graph back = parseTpg(parsed.tpg, parsed);
  ASSERT_EQ(back.nodes.size(), graph_->nodes.size());
  ASSERT_EQ(back.edges.size(), graph_->edges.size());
  for (std::size_t i = 0; i < back.edges.size(); ++i) {
    EXPECT_EQ(back.edges[i].from, graph_->edges[i].from);
    EXPECT_EQ(back.edges[i].to, graph_->edges[i].to);
    EXPECT_EQ(back.edges[i].why, graph_->edges[i].why);
  }
  EXPECT_EQ(tpgToJson(back, parsed), with.tpg);
  const std::string without = planToJson(*plan_);
  EXPECT_EQ(without.find("\"tpg\""), std::string::npos);
  EXPECT_TRUE(parsePlan(without, "without.json").tpg.empty());
}

TEST_F(SortingTpg, ParseRefusesACycleAndEdgesOutOfRange) {
  auto root = nlohmann::json::parse(tpgToJson(*graph_, *plan_));
  ASSERT_FALSE(root["edges"].empty());
  auto cyclic = root;
  const auto first = cyclic["edges"][0];
  cyclic["edges"].push_back({{"from", first["to"]}, {"to", first["from"]}, {"why", "swept"}});
  EXPECT_THROW(
      {
        try {
          parseTpg(cyclic.dump(), *plan_);
        } catch (const InputError& e) {
          EXPECT_NE(std::string(e.what()).find("cycle"), std::string::npos) << e.what();
          throw;
        }
      },
      InputError);
  auto out_of_range = root;
  out_of_range["edges"][0]["to"] = root["nodes"].size();
  EXPECT_THROW(parseTpg(out_of_range.dump(), *plan_), InputError);
  auto missing_event = root;
  for (std::size_t i = 0; i < missing_event["nodes"].size(); ++i) {
    if (missing_event["nodes"][i]["kind"] == "event") {
      missing_event["nodes"][i]["event"] = (missing_event["nodes"][i]["event"].get<int>() + 1) % static_cast<int>(plan_->events.size());
      break;
    }
  }
  EXPECT_THROW(parseTpg(missing_event.dump(), *plan_), InputError);
}

/// Runs the real binary; returns its exit status and fills `output`.
int runDashbench(const std::string& arguments, std::string& output) {
  const std::string out_path = ::testing::TempDir() + "tpg_cli_output.txt";
  const int status = std::system((std::string(DASHBENCH_BINARY) + " " + arguments + " > " + out_path + " 2>&1").c_str());
  std::ifstream in(out_path);
  output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return WEXITSTATUS(status);
}

TEST_F(SortingTpg, CliWritesThePlanWithItsGraphAndChecksReplays) {
  const std::string dir = ::testing::TempDir();
  saveScene(*scene_, dir + "tpg_scene.json");
  savePlan(*plan_, dir + "tpg_plan.json");
  std::string out;
  ASSERT_EQ(runDashbench("tpg --scene " + dir + "tpg_scene.json --plan " + dir + "tpg_plan.json --out " + dir +
                             "tpg_plan_with.json --check 20",
                         out),
            0)
      << out;
  EXPECT_NE(out.find("temporal plan graph of"), std::string::npos) << out;
  EXPECT_NE(out.find("replays: 20 draws, 0 failed"), std::string::npos) << out;
  const Plan with = loadPlan(dir + "tpg_plan_with.json");
  EXPECT_EQ(parseTpg(with.tpg, with).edges.size(), graph_->edges.size());
  // The stored graph is read back as it is; bad input is exit 2.
  EXPECT_EQ(runDashbench("tpg --scene " + dir + "tpg_scene.json --plan " + dir + "tpg_plan_with.json --check 2", out), 0) << out;
  EXPECT_EQ(runDashbench("tpg --scene " + dir + "tpg_scene.json --plan " + dir + "tpg_plan_with.json --drop-edge 100000 --check 2", out), 2) << out;
}

}  // namespace
}  // namespace dash::tpg
