// One phase accounting for both planners (docs/planners.md "Phases"): in the results database a run's
// phases add up to its stored total (within 1 ms), the planner's wall time is stored beside it and within
// 2 % of it, and the row says which accounting it follows. Real runs of both planners, through the
// dashbench binary's run-one.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/events/event_emitter.h"
#include "server/batch/batch_store.h"
#include "tests/batch/batch_test_util.h"

namespace dash::batch {
namespace {

using namespace testing;

TEST(PhaseAccounting, BothPlannersPhasesSumToTheStoredTotalWithTheWallTimeBesideIt) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const BatchSpec spec = specOf(sortingSpec("[4]", "[1]", R"([{"name":"lazy-dash"},{"name":"dash"}])", 120));
  BatchRunner runner;
  runner.start(spec, db_path, testOptions(2), [](const BatchProgress&) {});
  const BatchResult result = runner.wait();
  ASSERT_EQ(result.status, "finished") << result.error;
  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const auto runs = db.listRuns(log::RunFilter{.batch_id = result.batch_id, .limit = 100, .newest_first = false});
  ASSERT_EQ(runs.size(), 2u);
  for (const log::RunRecord& r : runs) {
    SCOPED_TRACE(r.meta.planner);
    EXPECT_EQ(r.status, log::RunStatus::Solved) << r.summary.error;
    ASSERT_TRUE(r.summary.total_time && r.summary.wall_time && r.summary.phase_seconds);
    EXPECT_EQ(r.summary.phase_accounting.value_or(0), 2);
    const double total = *r.summary.total_time;
    EXPECT_NEAR(log::phaseSum(*r.summary.phase_seconds), total, 1e-3);
    EXPECT_LE(std::abs(*r.summary.wall_time - total), 0.02 * total) << "wall " << *r.summary.wall_time;
    EXPECT_GT(total, 0.0);
  }
}

}  // namespace
}  // namespace dash::batch
