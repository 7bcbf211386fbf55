// The quick variants of the paper's figures (experiments/quick/*.json) run for real in CI: each
// through `dashbench batch run` with 2 workers into a fresh database, then `dashbench report`.
// Every run must end with a terminal status (solved, timeout or infeasible: a crash is a failure,
// and so is a run left running or cancelled) and the report must print the family's three tables
// with a row per planner. Whether a run solves depends on the machine's speed, so it is not
// asserted; the quick specs are tuned so that most Lazy-DaSH runs do on the 2-core build machine.
// One quick batch takes under a minute (experiments_test.cpp bounds its worst case); the tests
// share a lock, as each uses both cores.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <set>

#include "engine/log/results_db.h"
#include "server/batch/batch_spec.h"
#include "tests/batch/batch_test_util.h"
#include "tests/common/cli_run.h"

namespace dash::batch {
namespace {

namespace fs = std::filesystem;
using namespace testing;

const fs::path kQuick = fs::path(DASHBENCH_SOURCE_DIR) / "experiments" / "quick";

/// Runs the dashbench binary; returns (exit code, stdout and stderr).
std::pair<int, std::string> dashbench(const std::string& args) {
  test::CliRun r = test::runDashbench(args);
  return {r.exit_code, std::move(r.output)};
}

class QuickBatch : public ::testing::TestWithParam<std::string> {};

TEST_P(QuickBatch, RunsWithTwoWorkersAndReports) {
  const std::string spec_path = (kQuick / (GetParam() + ".json")).string();
  const BatchSpec spec = loadBatchSpec(spec_path);
  const std::size_t runs = countRuns(spec);
  TempDir dir;
  const std::string db_path = dir.file("quick.db");
  const std::string id = "quick-" + GetParam();

  const auto [run_code, run_out] =
      dashbench("batch run " + spec_path + " --db " + db_path + " --workers 2 --quiet --id " + id);
  EXPECT_EQ(run_code, 0) << run_out;
  EXPECT_NE(run_out.find("batch " + id + ": finished"), std::string::npos) << run_out;

  {
    const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
    const std::vector<log::RunRecord> records =
        db.listRuns(log::RunFilter{.batch_id = id, .limit = 100000, .newest_first = false, .include_plan = true});
    EXPECT_EQ(records.size(), runs);
    std::set<std::string> planners;
    for (const log::RunRecord& r : records) {
      SCOPED_TRACE(r.meta.planner + " " + r.meta.params_json + " seed " + std::to_string(r.meta.seed));
      planners.insert(r.meta.planner);
      EXPECT_TRUE(r.status == log::RunStatus::Solved || r.status == log::RunStatus::Timeout ||
                  r.status == log::RunStatus::Infeasible)
          << log::toString(r.status) << ": " << r.summary.error;
      EXPECT_FALSE(r.end_time.empty());
      if (r.status == log::RunStatus::Solved) {
        EXPECT_FALSE(r.summary.plan_json.empty());
      }
      EXPECT_GT(r.event_count, 0);
    }
    EXPECT_EQ(planners, (std::set<std::string>{"lazy-dash", "dash"}));
  }

  const auto [report_code, report] = dashbench("report " + db_path + " --batch " + id);
  EXPECT_EQ(report_code, 0) << report;
  EXPECT_NE(report.find("== " + spec.scenarios.at(0).family + " ("), std::string::npos) << report;
  for (const char* table : {"Representation sizes", "Time breakdown", "Success rate"}) {
    EXPECT_NE(report.find(table), std::string::npos) << table << "\n" << report;
  }
  const std::string success = report.substr(std::min(report.find("Success rate"), report.size()));
  for (const auto& p : spec.planners) {
    EXPECT_NE(success.find("  " + p.label + " "), std::string::npos) << p.label << "\n" << report;
  }
  // The report goes to the test log: the quick figures at a glance.
  std::printf("%s\n", report.c_str());
}

INSTANTIATE_TEST_SUITE_P(Figures, QuickBatch,
                         ::testing::Values("sorting", "wall", "shelf-wall", "stocking", "lab"),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (c == '-') c = '_';
                           }
                           return name;
                         });

}  // namespace
}  // namespace dash::batch
