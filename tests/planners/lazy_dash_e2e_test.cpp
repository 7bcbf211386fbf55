// End-to-end: generated scene -> Lazy-DaSH -> plan -> the project's validator, and the event stream
// against the reported sizes. Small cases only (timing goals live in experiments/, not here).
#include <gtest/gtest.h>

#include "engine/events/memory_sink.h"
#include "engine/plan/plan_validator.h"
#include "engine/planners/lazy_dash.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash {
namespace {

struct Case {
  const char* family;
  std::vector<std::pair<std::string, std::string>> params;
};

PlanResult solveCase(const Case& c, std::uint64_t seed, log::EventSink* sink, Scene& scene) {
  scene = generateScenario(c.family, c.params, seed, RobotLibrary::loadDefault());
  PlannerSettings settings;
  settings.seed = seed;
  settings.time_limit = 240;
  return makePlanner("lazy-dash")->solve(scene, settings, Deadline(settings.time_limit), sink);
}

void expectSolvedAndValid(const Case& c) {
  Scene scene;
  log::MemorySink sink;
  const PlanResult result = solveCase(c, 1, &sink, scene);
  ASSERT_EQ(result.outcome, PlanOutcome::kSolved) << result.message;
  ASSERT_TRUE(result.plan.has_value());
  const ValidationReport report = validatePlan(scene, *result.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  EXPECT_GT(result.plan->makespan, 0.0);
  // Every robot starts at home at t = 0 and the plan ends at home (the scene says so).
  for (const RobotTrajectory& r : result.plan->robots) EXPECT_EQ(r.points.front().t, 0.0);
  // The event stream holds exactly what the planner reports it built.
  const RepresentationCounts& n = result.stats.sizes;
  EXPECT_EQ(sink.count(log::Layer::Task, log::ElementKind::Vertex), n.task_vertices);
  EXPECT_EQ(sink.count(log::Layer::Task, log::ElementKind::Hyperarc), n.task_hyperarcs);
  EXPECT_EQ(sink.count(log::Layer::TaskExtended, log::ElementKind::Vertex), n.task_extended_vertices);
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Vertex), n.motion_vertices);
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Hyperarc), n.motion_hyperarcs);
  EXPECT_GT(n.motion_vertices, 0u);
}

TEST(LazyDashEndToEnd, SortingTwoRobotsTwoObjects) { expectSolvedAndValid({"sorting", {{"robots", "2"}, {"objects", "2"}}}); }

TEST(LazyDashEndToEnd, SortingFourRobotsEightObjects) {
  expectSolvedAndValid({"sorting", {{"robots", "4"}, {"objects", "8"}}});
}

// Handovers over the walls: the receiver approaches and both retreat clear of the partner's hand.
TEST(LazyDashEndToEnd, WallEightRobotsTwoWallsSixteenObjects) {
  expectSolvedAndValid({"wall", {{"robots", "8"}, {"walls", "2"}, {"objects", "16"}}});
}

// Cubbies: placements deep in a shelf, approached and left along the gripper's axis.
TEST(LazyDashEndToEnd, ShelfWallTwoRobotsEightObjects) {
  expectSolvedAndValid({"shelf-wall", {{"robots", "2"}, {"objects", "8"}}});
}

// Items in front must be moved out to staging posts and put back; new items come by a handover.
TEST(LazyDashEndToEnd, StockingTwoLayersEightObjects) {
  expectSolvedAndValid({"stocking", {{"layers", "2"}, {"objects", "8"}}});
}

TEST(LazyDashEndToEnd, LabTwoContainers) { expectSolvedAndValid({"lab", {{"containers", "2"}}}); }

TEST(LazyDashEndToEnd, TaskOnlyGivesATaskLevelFeasibleSchedule) {
  Scene scene = generateScenario("sorting", {{"robots", "4"}, {"objects", "8"}}, 2, RobotLibrary::loadDefault());
  PlannerSettings settings;
  settings.task_only = true;
  const PlanResult result = makePlanner("lazy-dash")->solve(scene, settings, Deadline(60), nullptr);
  ASSERT_EQ(result.outcome, PlanOutcome::kSolved) << result.message;
  EXPECT_FALSE(result.plan.has_value());
  EXPECT_NE(result.task_plan_json.find("\"handover\""), std::string::npos);
}

// A motion query that runs out of budget (roadmap and global sampling) first stays in the motion loop:
// motion constraints (logged as kind motion) make task conflict detection choose other transition
// configurations for the same task plan. Only when that plan's motion budget is spent does the failure
// become a task constraint (a ban on its hyperarc, logged as kind interaction) for as many task queries
// as it has failed (TaskLayerParams::max_ban_queries at most). When no schedule avoids the
// banned hyperarcs, the bans are lifted and the same hyperarcs go back to the motion layer with a larger
// budget: starved roadmaps end solved, not infeasible. (Wall: the way round a wall needs the roadmap. The
// straight segment is off: since approaches and retreats are Cartesian-dense, their farther ends let it
// round the walls of seed 1 and 2, so that no motion query failed.) Without resampling, the same run
// needs as many bans and lifts or more.
TEST(LazyDashEndToEnd, StarvedRoadmapsGetOtherConfigurationsAndMoreBudgetInsteadOfInfeasible) {
  const Scene scene = generateScenario("wall", {{"walls", "2"}, {"objects", "4"}}, 2, RobotLibrary::loadDefault());
  LazyDashParams params;
  params.motion.roadmap.query_samples = 3;
  params.motion.roadmap.tree_iterations = 3;  // global sampling starved too
  params.motion.straight_first = false;
  auto configurationConstraints = [](const log::MemorySink& sink) {
    int n = 0;
    for (const log::Event& e : sink.events())
      if (const auto* c = std::get_if<log::ConstraintEvent>(&e.payload))
        n += c->kind == log::ConstraintKind::Motion && c->action == log::ConstraintAction::Created &&
             c->content.find(" q=(") != std::string::npos && c->content.find(" in [") == std::string::npos;
    return n;
  };
  auto lifted = [](const log::MemorySink& sink) {
    return sink.countConstraints(log::ConstraintKind::Interaction, log::ConstraintAction::Lifted);
  };

  params.max_transition_resamples = 0;
  log::MemorySink banning;
  const PlanResult banned = LazyDash(params).solve(scene, {}, Deadline(240), &banning);
  ASSERT_EQ(banned.outcome, PlanOutcome::kSolved) << banned.message;
  EXPECT_TRUE(validatePlan(scene, *banned.plan).valid());
  // No motion constraint over transition configurations alone (the resampling kind); regions of
  // conflict resolution (world boxes, "in [x0, x1] ...") may still be learned.
  EXPECT_EQ(configurationConstraints(banning), 0);
  EXPECT_GT(banning.countConstraints(log::ConstraintKind::Interaction, log::ConstraintAction::Created), 0);
  EXPECT_GT(lifted(banning), 0);

  params.max_transition_resamples = 2;  // the default
  log::MemorySink resampling;
  const PlanResult resampled = LazyDash(params).solve(scene, {}, Deadline(240), &resampling);
  ASSERT_EQ(resampled.outcome, PlanOutcome::kSolved) << resampled.message;
  EXPECT_TRUE(validatePlan(scene, *resampled.plan).valid());
  EXPECT_GT(configurationConstraints(resampling), 0);
  EXPECT_EQ(resampled.stats.motion_constraints,
            resampling.countConstraints(log::ConstraintKind::Motion, log::ConstraintAction::Created));
  EXPECT_LE(lifted(resampling), lifted(banning));
  // Algorithm 1's loop shape: a motion query failure is a motion constraint first; a ban that follows
  // from one comes after it.
  int first_motion = -1, first_ban = -1;
  const std::vector<log::Event> events = resampling.events();
  for (int i = 0; i < static_cast<int>(events.size()); ++i) {
    const auto* c = std::get_if<log::ConstraintEvent>(&events[i].payload);
    if (c == nullptr || c->action != log::ConstraintAction::Created) continue;
    if (c->kind == log::ConstraintKind::Motion && first_motion < 0) first_motion = i;
    if (c->kind == log::ConstraintKind::Interaction && c->conflict.rfind("motion query", 0) == 0 && first_ban < 0)
      first_ban = i;
  }
  ASSERT_GE(first_motion, 0);
  if (first_ban >= 0) {
    EXPECT_LT(first_motion, first_ban);
  }
}

TEST(LazyDashEndToEnd, StopFlagEndsTheRunPromptly) {
  Scene scene = generateScenario("sorting", {{"robots", "4"}, {"objects", "8"}}, 1, RobotLibrary::loadDefault());
  std::atomic<bool> stop{true};
  const PlanResult result = makePlanner("lazy-dash")->solve(scene, {}, Deadline(600, &stop), nullptr);
  EXPECT_EQ(result.outcome, PlanOutcome::kCancelled);
}

}  // namespace
}  // namespace dash
