// DaSH on the paper's scenes (Wall with five robots and two walls is in dash_wall_test.cpp): it
// solves Lab; on Shelf-wall (the paper: not solved even with 2 robots within the time limit) it runs
// to its deadline or solves, having logged what it built, never "infeasible" and never with a plan
// that does not validate. Sorting with 4 robots and 8 objects is in the conformance suite.
#include <gtest/gtest.h>

#include "engine/dash/dash_planner.h"
#include "engine/events/memory_sink.h"
#include "engine/plan/plan_validator.h"
#include "engine/planners/planner.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

TEST(DashScenes, SolvesLabWithInspectionsAndSharedPlacements) {
  // Two gantries; each lid must be away from its container while it is inspected. The sanitisation
  // zone is small: a lid that finds no room of its own shares another lid's placement.
  const Scene scene = test::dashScene("lab", {{"containers", "2"}});
  auto planner = makePlanner("dash");
  PlannerSettings settings;
  log::MemorySink sink;
  const PlanResult r = planner->solve(scene, settings, Deadline(30.0), &sink);
  ASSERT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
  const ValidationReport report = validatePlan(scene, *r.plan);
  EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);
  int inspects = 0;
  for (const PlanEvent& e : r.plan->events) inspects += e.type == PlanEvent::Type::kInspect;
  EXPECT_EQ(inspects, static_cast<int>(scene.tasks.size()));
  EXPECT_GT(sink.countHyperarcs(log::Layer::Motion, "inspect"), 0);
}

TEST(DashScenes, ShelfWallEndsSolvedOrAtItsDeadlineAndLogsEverything) {
  const Scene scene = test::dashScene("shelf-wall", {{"robots", "2"}, {"objects", "2"}});
  auto planner = makePlanner("dash");
  PlannerSettings settings;
  settings.time_limit = 6.0;
  log::MemorySink sink;
  const PlanResult r = planner->solve(scene, settings, Deadline(settings.time_limit), &sink);
  EXPECT_TRUE(r.outcome == PlanOutcome::kTimeout || r.outcome == PlanOutcome::kSolved) << toString(r.outcome);
  if (r.plan) {
    EXPECT_TRUE(validatePlan(scene, *r.plan).valid());
  }
  EXPECT_EQ(r.message.find("internal error"), std::string::npos) << r.message;
  EXPECT_GT(sink.count(log::Layer::Task, log::ElementKind::Vertex), 0);
  EXPECT_EQ(sink.count(log::Layer::Task, log::ElementKind::Vertex), static_cast<std::int64_t>(r.stats.sizes.task_vertices));
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Vertex), static_cast<std::int64_t>(r.stats.sizes.motion_vertices));
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Hyperarc), static_cast<std::int64_t>(r.stats.sizes.motion_hyperarcs));
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::Frontier, log::ConstraintAction::Created), 0);
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::History, log::ConstraintAction::Created), 0);
  EXPECT_EQ(sink.countTaskSpaceExpansions(), 0);
  EXPECT_GT(sink.phaseSeconds(log::Phase::MotionConstruction), 0.0);
}

// A PRM-based planner never proves a generated (feasible) scene infeasible: on Shelf-wall, DaSH keeps
// growing its roadmaps (and, with a hyperpath, its constraint tree) until solved or the deadline.
TEST(DashScenes, ShelfWallRunsToTheDeadlineOrSolves) {
  const Scene scene = test::dashScene("shelf-wall", {{"robots", "2"}, {"objects", "2"}});
  DashPlanner planner;
  PlannerSettings settings;
  log::MemorySink sink;
  const PlanResult r = planner.solve(scene, settings, Deadline(20.0), &sink);
  EXPECT_NE(r.outcome, PlanOutcome::kInfeasible) << r.message;
  if (r.outcome == PlanOutcome::kSolved) {
    EXPECT_TRUE(validatePlan(scene, *r.plan).valid());
  } else {
    // Out of time wherever it was (on a loaded machine, possibly still building H_M).
    EXPECT_EQ(r.outcome, PlanOutcome::kTimeout) << r.message;
    EXPECT_NE(r.message.find("timeout"), std::string::npos) << r.message;
  }
  EXPECT_EQ(r.message.find("internal error"), std::string::npos) << r.message;
}

TEST(DashScenes, TaskOnlyStopsAfterTheCombinedQuery) {
  const Scene scene = test::dashScene("sorting", {{"robots", "2"}, {"objects", "1"}});
  auto planner = makePlanner("dash");
  PlannerSettings settings;
  settings.task_only = true;
  log::MemorySink sink;
  const PlanResult r = planner->solve(scene, settings, Deadline(30.0), &sink);
  ASSERT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
  EXPECT_FALSE(r.plan.has_value());
  EXPECT_NE(r.task_plan_json.find("\"steps\""), std::string::npos);
  EXPECT_NE(r.message.find("handover"), std::string::npos) << r.message;
  EXPECT_EQ(sink.phaseSeconds(log::Phase::ConflictResolution), 0.0);
}

}  // namespace
}  // namespace dash
