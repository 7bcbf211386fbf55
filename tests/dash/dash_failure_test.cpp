// DaSH's weakness, kept honest: without task constraint feedback or task space expansion it cannot
// order Shelf-wall's rear and front objects; it must end without a plan (timeout or infeasible),
// having logged what it built, never with a plan that does not validate.
#include <gtest/gtest.h>

#include "engine/log/memory_sink.h"
#include "engine/planners/planner.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

TEST(DashFailure, ShelfWallEndsWithoutAPlanAndLogsEverything) {
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

TEST(DashFailure, TaskOnlyStopsAfterTheCombinedQuery) {
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
