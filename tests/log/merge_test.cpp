#include <gtest/gtest.h>
#include <sqlite3.h>

#include "engine/log/db_tools.h"
#include "engine/log/dispatch_store.h"
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

DispatchRecord dispatchRecord(const std::string& id, const std::string& created, const std::string& state,
                              std::vector<std::string> robots) {
  DispatchRecord r{.id = id,
                   .created = created,
                   .started = state == "refused" ? "" : created,
                   .ended = state == "running" ? "" : created,
                   .state = state,
                   .reason = state == "aborted" ? "operator pressed stop" : "",
                   .scene = "sorting_r2_o2_s1",
                   .planner = "lazy-dash",
                   .requested_by = "alice",
                   .client = "127.0.0.1",
                   .time_scale = 0.765};
  for (const std::string& robot : robots) {
    r.arms.push_back(DispatchArmRecord{.robot = robot,
                                       .driver = robot == "ur5e_0" ? "ur" : "sim",
                                       .status = state == "running" ? "executing" : state,
                                       .result = state == "running" ? "" : (state == "aborted" ? "CANCELLED" : "SUCCESSFUL"),
                                       .samples = state == "running" ? 10 : 1200});
  }
  return r;
}

// (id, state, number of arms) of every dispatch in a file, by id.
std::map<std::string, std::pair<std::string, std::size_t>> dispatchesOf(const std::string& path) {
  const DispatchStore store(path, OpenMode::ReadOnly);
  std::map<std::string, std::pair<std::string, std::size_t>> out;
  for (const DispatchRecord& r : store.list(1000)) out[r.id] = {r.state, r.arms.size()};
  return out;
}

TEST(Merge, DispatchRecordsArriveOnceAndAFinishedOneReplacesItsActiveCopy) {
  testing::TempDir dir;
  const std::string a = dir.file("a.db"), b = dir.file("b.db"), out = dir.file("out.db");
  RunMetadata meta = testing::sampleMeta();
  meta.uuid = "5b0c7a52-0000-4000-8000-00000000000d";
  {
    ResultsDb db(a);
    testing::recordRun(db, meta, 3);
  }
  {
    DispatchStore store(a);
    DispatchRecord done = dispatchRecord("d1-0000aaaa-1", "2026-11-21T10:00:00.000Z", "succeeded", {"ur5e_0", "ur5e_1"});
    done.run_uuid = meta.uuid;
    store.save(done);
    store.save(dispatchRecord("d1-0000aaaa-2", "2026-11-21T10:01:00.000Z", "running", {"ur5e_0", "ur5e_1"}));
  }
  {
    DispatchStore store(b);
    // The same dispatch, copied from the same server after it ended: it replaces a's running copy.
    store.save(dispatchRecord("d1-0000aaaa-2", "2026-11-21T10:01:00.000Z", "aborted", {"ur5e_0", "ur5e_1"}));
    store.save(dispatchRecord("d2-0000bbbb-1", "2026-11-21T11:00:00.000Z", "refused", {"ur5e_0"}));
    // Another dispatch under a's first id (the old id format, two servers in the same millisecond).
    DispatchRecord other = dispatchRecord("d1-0000aaaa-1", "2026-11-21T10:00:00.000Z", "succeeded", {"ur5e_3"});
    other.client = "10.0.0.7";
    store.save(other);
  }

  const MergeReport first = mergeDatabases(out, {a, b});
  EXPECT_EQ(first.added, 1);
  EXPECT_EQ(first.dispatches_added, 4);  // a's two, b's refused one, b's other d1-0000aaaa-1
  EXPECT_EQ(first.dispatches_replaced, 1);
  EXPECT_EQ(first.dispatches_skipped, 0);
  auto merged = dispatchesOf(out);
  ASSERT_EQ(merged.size(), 4u);
  EXPECT_EQ(merged.at("d1-0000aaaa-1"), std::make_pair(std::string("succeeded"), std::size_t{2}));
  EXPECT_EQ(merged.at("d1-0000aaaa-2"), std::make_pair(std::string("aborted"), std::size_t{2}));
  EXPECT_EQ(merged.at("d2-0000bbbb-1"), std::make_pair(std::string("refused"), std::size_t{1}));
  std::string renamed;
  for (const auto& [id, _] : merged) {
    if (id.rfind("d1-0000aaaa-1-", 0) == 0) renamed = id;
  }
  ASSERT_EQ(renamed.size(), std::string("d1-0000aaaa-1-").size() + 8) << "the colliding id gets a suffix";
  const DispatchStore store(out, OpenMode::ReadOnly);
  const auto other = store.get(renamed);
  ASSERT_TRUE(other.has_value());
  EXPECT_EQ(other->client, "10.0.0.7");
  ASSERT_EQ(other->arms.size(), 1u);
  EXPECT_EQ(other->arms[0].robot, "ur5e_3");
  const auto aborted = store.get("d1-0000aaaa-2");
  EXPECT_EQ(aborted->reason, "operator pressed stop");
  EXPECT_EQ(aborted->arms[0].result, "CANCELLED");
  EXPECT_EQ(aborted->arms[1].samples, 1200);
  EXPECT_EQ(store.get("d1-0000aaaa-1")->run_uuid, meta.uuid);
  EXPECT_TRUE(ResultsDb(out, OpenMode::ReadOnly).getRun(meta.uuid).has_value());

  // Merging the same files again (in either order) adds nothing, and the finished copy stays.
  const MergeReport second = mergeDatabases(out, {b, a});
  EXPECT_EQ(second.dispatches_added, 0);
  EXPECT_EQ(second.dispatches_replaced, 0);
  EXPECT_EQ(second.dispatches_skipped, 5);
  EXPECT_EQ(dispatchesOf(out), merged);
  const DispatchStore again(out, OpenMode::ReadOnly);
  EXPECT_EQ(again.count(), 4);
  EXPECT_EQ(testing::integrityCheck(out), "ok");

  // Merged into a file that already holds a's running copy: replaced there too.
  const MergeReport into_a = mergeDatabases(a, {b});
  EXPECT_EQ(into_a.dispatches_replaced, 1);
  EXPECT_EQ(into_a.dispatches_added, 2);
  EXPECT_EQ(dispatchesOf(a).size(), 4u);
  EXPECT_EQ(dispatchesOf(a).at("d1-0000aaaa-2").first, "aborted");
}

}  // namespace
}  // namespace dash::log
