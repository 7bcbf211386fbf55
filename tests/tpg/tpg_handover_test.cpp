// The temporal plan graph where two arms approach a handover at once (engine/tpg, issue 39): the
// 4-robot / 8-object sorting plan (Lazy-DaSH, seed 1), whose givers and receivers move into the
// handover together. A receiver's finger may touch the object the giver holds but never enter it
// (the validator's rule), whatever the arms' delays: the graph must order the approaches so.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "engine/tpg/tpg.h"
#include "engine/tpg/tpg_replay.h"
#include "tests/tpg/tpg_test_util.h"

namespace dash::tpg {
namespace {

class HandoverTpg : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { case_ = new Case(planAndBuild(RobotLibrary::loadDefault(), "4", "8")); }
  static void TearDownTestSuite() { delete case_; }
  void SetUp() override { ASSERT_NE(case_->graph, nullptr) << "planning the 4/8 sorting scene failed"; }

  /// The times of the handovers: grasps of an object another robot still holds.
  static std::vector<std::pair<double, std::string>> handovers() {
    const Plan& plan = *case_->plan;
    std::vector<std::pair<double, std::string>> out;  // (t, "giver receiver")
    for (const PlanEvent& g : plan.events) {
      for (const PlanEvent& r : plan.events) {
        if (g.type == PlanEvent::Type::kGrasp && r.type == PlanEvent::Type::kRelease && g.object == r.object &&
            g.robot != r.robot && g.t <= r.t + 1e-6 && g.t >= r.t - 1.0) {
          out.emplace_back(g.t, r.robot + " " + g.robot);
        }
      }
    }
    return out;
  }

  static Case* case_;
};

Case* HandoverTpg::case_ = nullptr;

TEST_F(HandoverTpg, HundredDelayDrawsPassTheValidatorWhereBothArmsApproachAHandoverAtOnce) {
  ASSERT_FALSE(handovers().empty()) << "the 4/8 sorting plan hands cubes over";
  EXPECT_EQ(graphProblem(*case_->graph, *case_->plan), "");
  EXPECT_EQ(case_->graph->forced, 0);
  ReplayOptions options;  // the defaults of `dashbench tpg --check`
  options.draws = 100;
  const ReplayReport r = checkReplays(*case_->scene, *case_->plan, *case_->graph, options);
  EXPECT_EQ(r.failed, 0) << "draw " << r.first_failed_draw << ": " << r.first_problem;
  EXPECT_EQ(r.draws, 100);
  std::printf("[ measure  ] %zu nodes, %zu edges; makespan planned %.2f s, replays %.2f .. %.2f s\n",
              case_->graph->nodes.size(), case_->graph->edges.size(), r.planned_makespan, r.min_makespan,
              r.max_makespan);
}

TEST_F(HandoverTpg, WithoutAnEdgeIntoAHandoverApproachSomeDrawPutsAPartIntoTheHeldObject) {
  const Graph& graph = *case_->graph;
  const auto meets = handovers();
  int tried = 0, needed = 0;
  std::string example;
  for (std::size_t k = 0; k < graph.edges.size() && needed < 3; ++k) {  // 3 are enough to show it
    const Edge& e = graph.edges[k];
    const Node& to = graph.nodes[static_cast<std::size_t>(e.to)];
    if (e.why != Edge::Why::kSwept || to.kind != Node::Kind::kMotion || !to.moves) continue;
    // A motion that ends within 1 s before a handover between its arm and the edge's source arm.
    const std::string& from_arm = graph.robots[static_cast<std::size_t>(graph.nodes[static_cast<std::size_t>(e.from)].robot)];
    const std::string& to_arm = graph.robots[static_cast<std::size_t>(to.robot)];
    bool approach = false;
    for (const auto& [t, arms] : meets) {
      approach |= (arms == from_arm + " " + to_arm || arms == to_arm + " " + from_arm) && to.t1 <= t + 1e-6 && to.t1 >= t - 1.0;
    }
    if (!approach) continue;
    ++tried;
    ReplayOptions options;
    options.draws = 12;
    options.max_wait = 10.0;
    options.max_stretch = 6.0;
    options.wait_probability = 0.8;
    options.focus = e.from;
    const ReplayReport r = checkReplays(*case_->scene, *case_->plan, withoutEdge(graph, k), options);
    if (r.failed > 0 && r.first_problem.find("held by") != std::string::npos) {
      ++needed;
      if (example.empty()) example = "edge " + std::to_string(k) + ": " + r.first_problem;
    }
  }
  std::printf("[ measure  ] %d of the first %d swept edges into a handover approach are needed; e.g. %s\n", needed, tried,
              example.c_str());
  EXPECT_GT(tried, 0);
  EXPECT_GT(needed, 0);
}

}  // namespace
}  // namespace dash::tpg
