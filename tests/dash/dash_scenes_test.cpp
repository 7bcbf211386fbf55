// DaSH on the paper's scenes: it solves Wall with five robots (the paper: up to 10 objects), and it
// fails honestly where task-level feedback is needed: without task constraints or task space
// expansion it cannot order Shelf-wall's rear and front objects, so it must end without a plan
// (timeout or infeasible), having logged what it built, never with a plan that does not validate.
#include <gtest/gtest.h>

#include "engine/log/memory_sink.h"
#include "engine/plan/plan_validator.h"
#include "engine/planners/planner.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

TEST(DashScenes, SolvesWallWithFiveRobots) {
  const Scene scene = test::dashScene("wall", {{"robots", "5"}, {"walls", "1"}, {"objects", "3"}});
  auto planner = makePlanner("dash");
  PlannerSettings settings;
  settings.time_limit = 40.0;
  log::MemorySink sink;
  const PlanResult r = planner->solve(scene, settings, Deadline(settings.time_limit), &sink);
  ASSERT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
  ASSERT_TRUE(r.plan.has_value());
  const ValidationReport report = validatePlan(scene, *r.plan);
  EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);
  // Objects cross the wall the long way round: handovers between neighbours the wall does not cut.
  EXPECT_GT(sink.countHyperarcs(log::Layer::Motion, "handover"), 0);
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::Interaction, log::ConstraintAction::Created), 0);
}

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

TEST(DashScenes, ShelfWallEndsWithoutAPlanAndLogsEverything) {
  const Scene scene = test::dashScene("shelf-wall", {{"robots", "2"}, {"objects", "2"}});
  auto planner = makePlanner("dash");
  PlannerSettings settings;
  settings.time_limit = 8.0;
  log::MemorySink sink;
  const PlanResult r = planner->solve(scene, settings, Deadline(settings.time_limit), &sink);
  EXPECT_NE(r.outcome, PlanOutcome::kSolved) << r.message;
  EXPECT_TRUE(r.outcome == PlanOutcome::kTimeout || r.outcome == PlanOutcome::kInfeasible) << toString(r.outcome);
  EXPECT_FALSE(r.plan.has_value());
  EXPECT_EQ(r.message.find("internal error"), std::string::npos) << r.message;
  EXPECT_GT(r.stats.sizes.motion_vertices, 0u);
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Hyperarc), static_cast<std::int64_t>(r.stats.sizes.motion_hyperarcs));
  EXPECT_GT(sink.count(log::Layer::MotionExtended, log::ElementKind::Vertex), 0);
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::Frontier, log::ConstraintAction::Created), 0);
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::History, log::ConstraintAction::Created), 0);
  EXPECT_EQ(sink.countTaskSpaceExpansions(), 0);
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
