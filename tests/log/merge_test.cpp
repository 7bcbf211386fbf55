#include <gtest/gtest.h>
#include <sqlite3.h>

#include "engine/log/db_tools.h"
#include "engine/log/results_db.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

struct Counts {
  std::int64_t runs, events, constraints, phases, counters, progress, experiments, configs, tags;
  bool operator==(const Counts&) const = default;
};

Counts countsOf(const std::string& path) {
  ResultsDb db(path, OpenMode::ReadOnly);
  auto n = [&](const char* table) {
    return std::get<std::int64_t>(db.select(std::string("SELECT COUNT(*) FROM ") + table).rows.at(0).at(0));
  };
  return {n("dash_runs"), n("dash_events"), n("dash_constraints"), n("dash_phases"), n("dash_counters"),
          n("dash_progress"), n("dash_experiments"), n("dash_planner_configs"), n("dash_run_tags")};
}

// Per run uuid: its event count in the file (to check that events followed their run).
std::map<std::string, std::int64_t> eventsPerRun(const std::string& path) {
  ResultsDb db(path, OpenMode::ReadOnly);
  std::map<std::string, std::int64_t> out;
  for (const auto& row : db.select("SELECT r.uuid, COUNT(e.seq) FROM dash_runs r LEFT JOIN dash_events e "
                                   "ON e.run_id = r.id GROUP BY r.uuid").rows) {
    out[std::get<std::string>(row[0])] = std::get<std::int64_t>(row[1]);
  }
  return out;
}

TEST(Merge, RunsArriveOnceWithTheirEventsAndMergingAgainChangesNothing) {
  testing::TempDir dir;
  const std::string a = dir.file("a.db"), b = dir.file("b.db"), out = dir.file("out.db");
  {
    ResultsDb db(a);
    db.putBatch(BatchRecord{.id = "batch-a", .name = "worker a"});
    RunMetadata meta = testing::sampleMeta();
    meta.batch_id = "batch-a";
    const std::string uuid = testing::recordRun(db, meta, 12);
    db.addTag(uuid, "from-a");
    testing::recordRun(db, testing::sampleMeta("sorting", R"({"robots":4,"objects":8})"), 7);
  }
  {
    ResultsDb db(b);
    testing::recordRun(db, testing::sampleMeta(), 9);  // same experiment as in a: must not duplicate it
    testing::recordRun(db, testing::sampleMeta("lab", R"({"containers":8})", "dash"), 4);
  }
  std::map<std::string, std::int64_t> expected = eventsPerRun(a);
  expected.merge(eventsPerRun(b));

  const MergeReport first = mergeDatabases(out, {a, b});
  EXPECT_EQ(first.added, 4);
  EXPECT_EQ(first.skipped, 0);
  const Counts once = countsOf(out);
  EXPECT_EQ(once.runs, 4);
  EXPECT_EQ(once.experiments, 3);
  EXPECT_EQ(once.configs, 2);
  EXPECT_EQ(once.tags, 1);
  EXPECT_EQ(eventsPerRun(out), expected);

  EXPECT_THROW(mergeDatabases(out, {out}), InputError);
  const MergeReport second = mergeDatabases(out, {a, b});
  EXPECT_EQ(second.added, 0);
  EXPECT_EQ(second.skipped, 4);
  EXPECT_EQ(countsOf(out), once);
  EXPECT_EQ(eventsPerRun(out), expected);

  ResultsDb merged(out, OpenMode::ReadOnly);
  EXPECT_EQ(merged.listBatches().size(), 1u);
  EXPECT_EQ(merged.listRuns(RunFilter{.batch_id = "batch-a"}).size(), 1u);
  // Planner Arena's view has every family's parameters after the merge.
  const SqlRows columns = merged.select("SELECT name FROM pragma_table_info('experiments')");
  std::set<std::string> names;
  for (const auto& row : columns.rows) names.insert(std::get<std::string>(row[0]));
  EXPECT_TRUE(names.count("containers") && names.count("robots") && names.count("objects"));
  EXPECT_EQ(testing::integrityCheck(out), "ok");
}

TEST(Merge, AFinishedRunReplacesTheSameRunLeftRunning) {
  testing::TempDir dir;
  const std::string partial = dir.file("partial.db"), complete = dir.file("complete.db");
  RunMetadata meta = testing::sampleMeta();
  meta.uuid = "5b0c7a52-0000-4000-8000-000000000001";
  {
    ResultsDb db(partial);
    db.beginRun(meta);  // never finished
  }
  {
    ResultsDb db(complete);
    testing::recordRun(db, meta, 5);
  }
  ResultsDb db(partial);
  const MergeReport r = db.mergeFrom(complete);
  EXPECT_EQ(r.replaced, 1);
  EXPECT_EQ(r.added, 0);
  const auto run = db.getRun(meta.uuid);
  EXPECT_EQ(run->status, RunStatus::Solved);
  EXPECT_EQ(run->event_count, ResultsDb(complete, OpenMode::ReadOnly).getRun(meta.uuid)->event_count);
  EXPECT_EQ(eventsPerRun(partial).at(meta.uuid), eventsPerRun(complete).at(meta.uuid));
  EXPECT_EQ(db.info().runs, 1);
}

TEST(Merge, AnOlderInputIsMigratedInACopyAndLeftUntouched) {
  testing::TempDir dir;
  const std::string old = dir.file("old.db"), out = dir.file("out.db");
  {
    ResultsDb db(old);
    testing::recordRun(db, testing::sampleMeta(), 3);
  }
  // Make it look like a version-1 file: drop version 2's additions.
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open(old.c_str(), &raw), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw,
                         "DROP TABLE dash_run_tags; ALTER TABLE dash_runs DROP COLUMN note; "
                         "ALTER TABLE dash_runs DROP COLUMN exit_signal; PRAGMA user_version = 1;",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(raw);

  EXPECT_EQ(mergeDatabases(out, {old}).added, 1);
  sqlite3_open(old.c_str(), &raw);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(raw, "PRAGMA user_version", -1, &st, nullptr);
  sqlite3_step(st);
  EXPECT_EQ(sqlite3_column_int(st, 0), 1);
  sqlite3_finalize(st);
  sqlite3_close(raw);
}

}  // namespace
}  // namespace dash::log
