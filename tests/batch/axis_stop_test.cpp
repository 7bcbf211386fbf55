// The axis stop rule (server/batch/axis_stop.h): a planner that fails a size on every seed skips the
// larger sizes of its line; the spec option, the duration estimate, and a real batch run and resume.
#include <gtest/gtest.h>

#include <sqlite3.h>

#include <regex>

#include "server/batch/axis_stop.h"
#include "server/batch/batch_report.h"
#include "server/batch/batch_store.h"
#include "tests/batch/batch_test_util.h"

namespace dash::batch {
namespace {

using namespace testing;

std::string stopSpec(const std::string& planners, const std::string& objects = "[1, 2, 3]") {
  return R"({"name":"axis","time_limit":20,"memory_limit":2048,"scenarios":[{"family":"sorting",)"
         R"("params":{"robots":2,"objects":)" + objects + R"(},"stop_axis":"objects"}],"planners":)" + planners +
         R"(,"seeds":[1, 2]})";
}
const char* kAborts = R"({"name":"dash","settings":{"test_fault":"abort"},"label":"aborts"})";

RunSpec run(int objects, std::uint64_t seed, const std::string& label = "p") {
  RunSpec r;
  r.family = "sorting";
  r.params = {{"robots", 2}, {"objects", objects}};
  r.seed = seed;
  r.label = label;
  r.stop_axis = "objects";
  r.time_limit = 10;
  return r;
}

TEST(AxisStop, AFailedSizeSkipsTheLargerOnesOfItsLineOnly) {
  const std::vector<RunSpec> runs = {run(1, 1), run(1, 2), run(2, 1), run(2, 2), run(3, 1), run(3, 2),
                                     run(3, 1, "q")};
  AxisStop rule(runs);
  EXPECT_EQ(rule.decide(run(1, 1)).verdict, AxisStop::Verdict::kRun);
  EXPECT_EQ(rule.decide(run(2, 1)).verdict, AxisStop::Verdict::kWait);  // size 1 not judged yet
  rule.finished(run(1, 1), false);
  EXPECT_EQ(rule.decide(run(2, 1)).verdict, AxisStop::Verdict::kWait);
  rule.finished(run(1, 2), true);  // one seed solved: size 1 did not fail on every seed
  EXPECT_EQ(rule.decide(run(2, 1)).verdict, AxisStop::Verdict::kRun);
  EXPECT_EQ(rule.decide(run(3, 1)).verdict, AxisStop::Verdict::kWait);
  rule.finished(run(2, 1), false);
  rule.finished(run(2, 2), false);
  const AxisStop::Decision d = rule.decide(run(3, 2));
  EXPECT_EQ(d.verdict, AxisStop::Verdict::kSkip);
  EXPECT_NE(d.reason.find("objects=2"), std::string::npos) << d.reason;
  EXPECT_EQ(rule.decide(run(3, 1, "q")).verdict, AxisStop::Verdict::kRun);  // another planner's line
  RunSpec plain = run(3, 1);
  plain.stop_axis.clear();
  EXPECT_EQ(rule.decide(plain).verdict, AxisStop::Verdict::kRun);  // no rule on this entry
}

TEST(AxisStop, SpecOptionIsParsedCheckedAndStoredWithEachRun) {
  const BatchSpec spec = specOf(stopSpec(std::string("[") + kTaskOnly + "]"));
  ASSERT_EQ(spec.scenarios.size(), 1u);
  EXPECT_EQ(spec.scenarios[0].stop_axis, "objects");
  const std::vector<RunSpec> runs = expandRuns(spec);
  for (const RunSpec& r : runs) {
    EXPECT_EQ(r.stop_axis, "objects");
    EXPECT_EQ(RunSpec::fromJson(r.toJson()).stop_axis, "objects");
  }
  std::string bad = stopSpec(std::string("[") + kTaskOnly + "]");
  bad.replace(bad.find("\"stop_axis\":\"objects\""), 21, "\"stop_axis\":\"boxes\"");
  try {
    specOf(bad);
    FAIL() << "an unknown stop axis was accepted";
  } catch (const SpecError& e) {
    EXPECT_EQ(e.kind(), SpecErrorKind::kBadValue);
    EXPECT_NE(std::string(e.what()).find("stop_axis"), std::string::npos) << e.what();
  }
}

TEST(AxisStop, PlanPrintsADurationEstimate) {
  const BatchSpec spec = specOf(stopSpec(std::string("[") + kTaskOnly + "]"));
  const std::vector<RunSpec> runs = expandRuns(spec);  // 3 sizes x 2 seeds, 20 s each
  const DurationEstimate one = estimateDuration(runs, 1, 0.0);
  EXPECT_DOUBLE_EQ(one.worst_seconds, 6 * 20.0);
  EXPECT_DOUBLE_EQ(one.stopped_seconds, 2 * 20.0);
  EXPECT_DOUBLE_EQ(estimateDuration(runs, 2, 0.0).worst_seconds, 3 * 20.0);
  const std::string text = formatRunList(spec, runs, 2);
  EXPECT_NE(text.find("duration with 2 workers: at most"), std::string::npos) << text;
}

/// Forgets the skips of the runs at objects=10 (as if the runner had died before reaching them).
void forgetSkipsAt10(const std::string& db_path, const std::string& id) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(db_path.c_str(), &db), SQLITE_OK);
  const std::string sql =
      "DELETE FROM dash_batch_skipped WHERE batch_id = '" + id + "' AND run_key LIKE '%objects=10%'";
  EXPECT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK);
  EXPECT_EQ(sqlite3_changes(db), 2);
  sqlite3_close(db);
}

TEST(AxisStop, ABatchSkipsWhatTheRuleStopsAndResumeRespectsIt) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  // Sizes 1, 2, 10: the report must list them in that order, not as text ("10" before "2").
  const BatchSpec spec = specOf(stopSpec(std::string("[") + kAborts + "," + kTaskOnly + "]", "[1, 2, 10]"));
  BatchRunner runner;
  const std::string id = runner.start(spec, db_path, testOptions(1));
  const BatchResult result = runner.wait();
  ASSERT_EQ(result.status, "finished") << result.error;
  // 3 sizes x 2 seeds x 2 planners: "aborts" crashes both seeds at objects=1, then skips 2 and 3.
  EXPECT_EQ(result.progress.total, 12);
  EXPECT_EQ(result.progress.done, 12);
  EXPECT_EQ(result.progress.crashed, 2);
  EXPECT_EQ(result.progress.solved, 6);
  EXPECT_EQ(result.progress.axis_skipped, 4);
  {
    const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
    EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_runs WHERE batch_id = ?", {id}), 8);
    int aborted = 0;
    for (const log::RunRecord& r :
         db.listRuns(log::RunFilter{.batch_id = id, .limit = 100, .newest_first = false}))
      aborted += r.meta.planner_config_name == "aborts";
    EXPECT_EQ(aborted, 2);
    const BatchStore store(db_path, log::OpenMode::ReadOnly);
    int skipped = 0;
    for (const StoredRun& r : store.runs(id)) {
      if (r.skipped.empty()) continue;
      ++skipped;
      EXPECT_TRUE(r.complete());
      EXPECT_EQ(r.spec.label, "aborts");
      EXPECT_NE(r.skipped.find("objects=1"), std::string::npos) << r.skipped;
    }
    EXPECT_EQ(skipped, 4);
    const std::vector<BatchInfo> info = listBatchInfo(db_path, id);
    ASSERT_EQ(info.size(), 1u);
    EXPECT_EQ(info[0].by_status.at("skipped"), 4);
    EXPECT_EQ(info[0].pending, 0);
    EXPECT_NE(formatBatchInfo(info).find("skipped"), std::string::npos);
    const std::string report = formatReport(db, ReportOptions{.batch_id = id});
    const std::size_t section = report.find("Skipped by the axis stop rule");
    ASSERT_NE(section, std::string::npos) << report;
    const std::size_t skipped_2 = report.find("robots=2 objects=2 ", section);
    const std::size_t skipped_10 = report.find("robots=2 objects=10 ", section);
    ASSERT_NE(skipped_2, std::string::npos) << report;
    ASSERT_NE(skipped_10, std::string::npos) << report;
    EXPECT_LT(skipped_2, skipped_10) << "skipped sizes in the spec's order:\n" << report.substr(section);
    // Where each planner breaks: "aborts" solved no size and was stopped after objects=1; the
    // task-only planner solved every seed up to objects=10.
    const std::size_t breaks = report.find("Where each planner breaks");
    ASSERT_NE(breaks, std::string::npos) << report;
    // The last column lists every finished size some seed failed, with solved/seeds.
    const std::regex aborts(R"(robots=2\s+aborts\s+objects\s+-\s+-\s+1\s+2\s+0\s+1: 0/2\n)");
    const std::regex task_only(R"(robots=2\s+lazy-task\s+objects\s+10\s+10\s+-\s+-\s+0\s+-\n)");
    EXPECT_TRUE(std::regex_search(report.substr(breaks), aborts)) << report.substr(breaks);
    EXPECT_TRUE(std::regex_search(report.substr(breaks), task_only)) << report.substr(breaks);
  }
  // Resume after the skips at objects=10 were lost: the rule, rebuilt from the stored results, skips
  // them again instead of running them.
  forgetSkipsAt10(db_path, id);
  BatchRunner again;
  again.resume(id, db_path, testOptions(1));
  const BatchResult resumed = again.wait();
  ASSERT_EQ(resumed.status, "finished") << resumed.error;
  EXPECT_EQ(resumed.progress.axis_skipped, 4);
  EXPECT_EQ(resumed.progress.crashed, 2);
  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_runs WHERE batch_id = ?", {id}), 8);
  EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_batch_skipped WHERE batch_id = ?", {id}), 4);
}

}  // namespace
}  // namespace dash::batch
