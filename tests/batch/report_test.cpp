// `dashbench report` tables (medians across seeds) and the batch CLI (plan, run, status, report).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <regex>

#include "server/batch/batch_report.h"
#include "tests/batch/batch_test_util.h"
#include "tests/common/cli_run.h"

namespace dash::batch {
namespace {

using namespace testing;

/// One finished run with the given task sizes and times.
void addRun(log::ResultsDb& db, const std::string& batch, int robots, std::uint64_t seed, log::RunStatus status,
            std::int64_t task_vertices, double task_query, double total, const std::string& planner = "lazy-dash",
            const std::string& error = "") {
  const std::string uuid =
      db.beginRun(log::RunMetadata{.batch_id = batch,
                                   .family = "sorting",
                                   .params_json = R"({"robots":)" + std::to_string(robots) + R"(,"objects":8})",
                                   .seed = seed,
                                   .planner = planner,
                                   .planner_config_name = planner});
  log::RunSummary s;
  s.status = status;
  s.total_time = total;
  log::PhaseTotals phases{};
  phases[static_cast<int>(log::Phase::TaskQuery)] = task_query;
  s.phase_seconds = phases;
  log::RepresentationSizes sizes;
  sizes.vertices[0] = task_vertices;
  sizes.hyperarcs[0] = 2 * task_vertices;
  s.sizes = sizes;
  s.error = error;
  db.finishRun(uuid, s);
}

std::string lineWith(const std::string& text, const std::string& section, const std::string& start) {
  const auto at = text.find(section);
  if (at == std::string::npos) return "";
  std::size_t pos = at;
  while ((pos = text.find('\n', pos)) != std::string::npos) {
    ++pos;
    const std::string line = text.substr(pos, text.find('\n', pos) - pos);
    if (line.empty()) return "";
    if (line.find(start) != std::string::npos) return line;
  }
  return "";
}

TEST(Report, MediansAcrossSeedsPerFamilyParamsAndPlanner) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 2, 3}), 2.5);
  EXPECT_TRUE(std::isnan(median({})));

  TempDir dir;
  log::ResultsDb db(dir.file("r.db"));
  db.putBatch(log::BatchRecord{.id = "b1", .name = "t"});
  addRun(db, "b1", 4, 1, log::RunStatus::Solved, 10, 0.5, 1.0);
  addRun(db, "b1", 4, 2, log::RunStatus::Solved, 30, 1.5, 3.0);
  addRun(db, "b1", 4, 3, log::RunStatus::Solved, 20, 1.0, 2.0);
  addRun(db, "b1", 4, 4, log::RunStatus::Timeout, 99, 9.0, 9.0);
  addRun(db, "b1", 8, 1, log::RunStatus::Crashed, 0, 0, 0.1);
  addRun(db, "b1", 6, 1, log::RunStatus::Crashed, 0, 0, 180, "lazy-dash",
         "out of memory (memory limit 16384 MB): out of memory (std::bad_alloc)");
  addRun(db, "b1", 4, 1, log::RunStatus::Infeasible, 5, 0.25, 0.5, "dash");
  addRun(db, "other", 4, 1, log::RunStatus::Solved, 1000, 100, 100);  // another batch

  const std::string text = formatReport(db, ReportOptions{.batch_id = "b1"});
  EXPECT_NE(text.find("== sorting"), std::string::npos) << text;
  EXPECT_EQ(text.find("1000"), std::string::npos) << "another batch leaked in:\n" << text;
  // Sizes: median 20 vertices, 40 hyperarcs over the 3 solved runs of robots=4 lazy-dash.
  const std::string sizes = lineWith(text, "Representation sizes", "robots=4 objects=8  lazy-dash");
  EXPECT_TRUE(std::regex_search(sizes, std::regex(R"(lazy-dash\s+3\s+20\s+40\s)"))) << sizes << "\n" << text;
  // Times: task query median 1.000 s, total 2.000 s.
  const std::string times = lineWith(text, "Time breakdown", "robots=4 objects=8  lazy-dash");
  EXPECT_TRUE(std::regex_search(times, std::regex(R"(lazy-dash\s+3\s+0\.000\s+1\.000\s)"))) << times;
  EXPECT_NE(times.find("2.000"), std::string::npos) << times;
  // Success: 3 of 4 for lazy-dash at robots=4; dash infeasible; robots=8 crashed; robots=6 out of
  // memory (a crash whose error says so, counted apart).
  EXPECT_NE(text.find("infeasible  out of memory  crashed  success"), std::string::npos) << text;
  const std::string success = lineWith(text, "Success rate", "robots=4 objects=8  lazy-dash");
  EXPECT_TRUE(std::regex_search(success, std::regex(R"(4\s+3\s+1\s+0\s+0\s+0\s+75%)"))) << success;
  const std::string dash = lineWith(text, "Success rate", "robots=4 objects=8  dash");
  EXPECT_TRUE(std::regex_search(dash, std::regex(R"(1\s+0\s+0\s+1\s+0\s+0\s+0%)"))) << dash;
  const std::string crashed = lineWith(text, "Success rate", "robots=8");
  EXPECT_TRUE(std::regex_search(crashed, std::regex(R"(1\s+0\s+0\s+0\s+0\s+1\s+0%)"))) << crashed;
  const std::string oom = lineWith(text, "Success rate", "robots=6");
  EXPECT_TRUE(std::regex_search(oom, std::regex(R"(1\s+0\s+0\s+0\s+1\s+0\s+0%)"))) << oom;
  // Rows with no solved run show '-'.
  EXPECT_NE(lineWith(text, "Representation sizes", "robots=4 objects=8  dash").find(" -"), std::string::npos);

  // --all-runs: the timeout joins the medians (10, 20, 30, 99 -> 25).
  const std::string all = formatReport(db, ReportOptions{.batch_id = "b1", .include_unsolved = true});
  const std::string all_sizes = lineWith(all, "Representation sizes", "robots=4 objects=8  lazy-dash");
  EXPECT_TRUE(std::regex_search(all_sizes, std::regex(R"(lazy-dash\s+4\s+25\s+50\s)"))) << all_sizes;
}

/// Runs the dashbench binary; returns (exit code, stdout).
std::pair<int, std::string> cli(const std::string& args) {
  test::CliRun r = test::runDashbench(args, test::Stderr::kDrop);
  return {r.exit_code, std::move(r.output)};
}

/// A finished run of `planner` on sorting robots=2 objects=2, seed `seed`, with a 10 s time limit.
void addTimedRun(log::ResultsDb& db, const std::string& planner, std::uint64_t seed, log::RunStatus status, double total) {
  const std::string uuid = db.beginRun(log::RunMetadata{.batch_id = "p",
                                                        .family = "sorting",
                                                        .params_json = R"({"robots":2,"objects":2})",
                                                        .seed = seed,
                                                        .planner = "lazy-dash",
                                                        .planner_config_name = planner,
                                                        .time_limit = 10.0});
  log::RunSummary s;
  s.status = status;
  s.total_time = total;
  db.finishRun(uuid, s);
}

TEST(Report, PairedComparisonKeepsFailuresAsCensoredPairsWithIntervals) {
  // The "mixed" case of tests/figures/paired_stats_cases.json, as a batch: seeds 1-3 both solved
  // (ratios 1/2, 1, 1/4), seed 4 a solved against b's timeout, seed 5 both timed out, seed 6 the
  // other way round.
  TempDir dir;
  log::ResultsDb db(dir.file("r.db"));
  db.putBatch(log::BatchRecord{.id = "p", .name = "paired"});
  const double a[] = {2, 3, 1, 5, 10.1, 10.1}, b[] = {4, 3, 4, 10.2, 10.3, 8};
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    addTimedRun(db, "fast", seed, a[seed - 1] > 10 ? log::RunStatus::Timeout : log::RunStatus::Solved, a[seed - 1]);
    addTimedRun(db, "slow", seed, b[seed - 1] > 10 ? log::RunStatus::Timeout : log::RunStatus::Solved, b[seed - 1]);
  }
  const std::string text = formatReport(db, ReportOptions{.batch_id = "p"});
  const std::string all = lineWith(text, "Paired comparison", "  all ");
  // pairs 6, both solved 3, geometric mean ratio 0.5 with t(0.975; 2) interval [0.0894, 2.80], 3 / 1 / 2
  // decided for a / b / undecided, sign test p = 2 * 5 / 16, success 4 of 6 with Wilson [30%, 90%].
  EXPECT_TRUE(std::regex_search(
      all, std::regex(R"(fast / slow\s+6\s+3\s+0\.5\s+\[0\.0894, 2\.8\]\s+3\s+1\s+2\s+0\.625\s+4/6 \[30%, 90%\]\s+4/6 \[30%, 90%\])")))
      << all << "\n" << text;
  EXPECT_NE(lineWith(text, "Paired comparison", "robots=2 objects=2  fast / slow"), "") << text;
  // The success table gives each configuration's Wilson interval.
  const std::string success = lineWith(text, "Success rate", "robots=2 objects=2  fast");
  EXPECT_TRUE(std::regex_search(success, std::regex(R"(67%\s+\[30%, 90%\])"))) << success;
}

TEST(BatchCli, PlanRunStatusAndReport) {
  TempDir dir;
  const std::string spec = dir.write("tiny.json", sortingSpec("[4, 6]", "[1]", std::string("[") + kTaskOnly + "]"));
  const std::string db = dir.file("results.db");

  auto [plan_code, plan] = cli("batch plan " + spec);
  EXPECT_EQ(plan_code, 0);
  EXPECT_NE(plan.find("2 runs"), std::string::npos) << plan;
  EXPECT_NE(plan.find("sorting/robots=4,objects=6/seed=1/lazy-task"), std::string::npos) << plan;
  EXPECT_FALSE(std::filesystem::exists(db)) << "plan must not run anything";

  const std::string bad =
      dir.write("bad.json", R"({"name":"x","scenarios":[],"planners":[{"name":"lazy-dash"}],"seeds":[1]})");
  EXPECT_EQ(cli("batch plan " + bad).first, 2);

  auto [run_code, run] = cli("batch run " + spec + " --db " + db + " --workers 2 --quiet --id tiny-1");
  EXPECT_EQ(run_code, 0) << run;
  EXPECT_NE(run.find("batch tiny-1: finished"), std::string::npos) << run;
  EXPECT_NE(run.find("2 solved"), std::string::npos) << run;

  auto [status_code, status] = cli("batch status --db " + db);
  EXPECT_EQ(status_code, 0);
  EXPECT_TRUE(std::regex_search(status, std::regex(R"(tiny-1\s+test\s+finished\s+2\s+2\s)"))) << status;
  EXPECT_EQ(cli("batch status --db " + db + " nope").first, 2);

  auto [report_code, report] = cli("report " + db + " --batch tiny-1");
  EXPECT_EQ(report_code, 0);
  EXPECT_NE(report.find("== sorting"), std::string::npos) << report;
  EXPECT_NE(report.find("Representation sizes"), std::string::npos) << report;
  EXPECT_NE(report.find("Time breakdown"), std::string::npos) << report;
  EXPECT_NE(report.find("100%"), std::string::npos) << report;
}

}  // namespace
}  // namespace dash::batch
