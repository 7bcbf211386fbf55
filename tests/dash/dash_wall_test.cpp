// DaSH solves Wall with five robots and two walls (the paper: up to 10 objects), in an executable of
// its own: the exhaustive motion hypergraph of five robots takes ~20 s to build on an idle machine.
#include <gtest/gtest.h>

#include "engine/events/memory_sink.h"
#include "engine/plan/plan_validator.h"
#include "engine/planners/planner.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

TEST(DashWall, SolvesWallWithFiveRobotsAndTwoWalls) {
  const Scene scene = test::dashScene("wall", {{"robots", "5"}, {"walls", "2"}, {"objects", "4"}});
  auto planner = makePlanner("dash");
  PlannerSettings settings;
  settings.time_limit = 120.0;  // a ceiling for a loaded machine: the run stops once solved (~20 s idle)
  log::MemorySink sink;
  const PlanResult r = planner->solve(scene, settings, Deadline(settings.time_limit), &sink);
  ASSERT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
  ASSERT_TRUE(r.plan.has_value());
  const ValidationReport report = validatePlan(scene, *r.plan);
  EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);
  // Objects cross the walls the long way round: handovers between neighbours no wall cuts.
  EXPECT_GT(sink.countHyperarcs(log::Layer::Motion, "handover"), 0);
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::Interaction, log::ConstraintAction::Created), 0);
}

}  // namespace
}  // namespace dash
