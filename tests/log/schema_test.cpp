#include <gtest/gtest.h>
#include <sqlite3.h>

#include "engine/log/dispatch_store.h"
#include "engine/log/results_db.h"
#include "engine/log/results_schema.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

// Schema version 1 exactly as released: a frozen copy (never update it). If this test fails after
// a schema change, the change needs a new migration instead of an edit of an old one.
constexpr const char* kFrozenV1 = R"sql(
CREATE TABLE dash_batches (
  id TEXT PRIMARY KEY,
  name TEXT NOT NULL DEFAULT '',
  spec TEXT NOT NULL DEFAULT '{}',
  created TEXT NOT NULL,
  status TEXT NOT NULL DEFAULT 'queued'
);
CREATE TABLE dash_experiments (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  family TEXT NOT NULL,
  params TEXT NOT NULL,
  version TEXT NOT NULL,
  UNIQUE (family, params, version)
);
CREATE TABLE dash_planner_configs (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  name TEXT NOT NULL,
  planner TEXT NOT NULL,
  settings TEXT NOT NULL,
  UNIQUE (name, planner, settings)
);
CREATE TABLE dash_runs (
  id INTEGER PRIMARY KEY AUTOINCREMENT,
  uuid TEXT NOT NULL UNIQUE,
  batch_id TEXT,
  experiment_id INTEGER NOT NULL REFERENCES dash_experiments(id),
  planner_config_id INTEGER NOT NULL REFERENCES dash_planner_configs(id),
  family TEXT NOT NULL,
  scene TEXT,
  params TEXT NOT NULL,
  seed INTEGER NOT NULL,
  planner TEXT NOT NULL,
  planner_settings TEXT NOT NULL,
  time_limit REAL,
  memory_limit REAL,
  code_version TEXT NOT NULL,
  host TEXT NOT NULL,
  cpu_info TEXT,
  start_time TEXT NOT NULL,
  end_time TEXT,
  status TEXT NOT NULL,
  error TEXT,
  total_time REAL,
  time_task_construction REAL,
  time_task_query REAL,
  time_task_conflict_detection REAL,
  time_motion_construction REAL,
  time_motion_query REAL,
  time_conflict_resolution REAL,
  time_other REAL,
  iterations INTEGER,
  task_vertices INTEGER,
  task_hyperarcs INTEGER,
  task_extended_vertices INTEGER,
  task_extended_hyperarcs INTEGER,
  motion_vertices INTEGER,
  motion_hyperarcs INTEGER,
  motion_extended_vertices INTEGER,
  motion_extended_hyperarcs INTEGER,
  roadmap_vertices INTEGER,
  roadmap_edges INTEGER,
  constraints_frontier INTEGER,
  constraints_history INTEGER,
  constraints_motion INTEGER,
  constraints_interaction INTEGER,
  task_space_expansions INTEGER,
  collision_checks INTEGER,
  collision_checks_eager INTEGER,
  collision_checks_lazy INTEGER,
  makespan REAL,
  path_length REAL,
  peak_memory REAL,
  plan TEXT,
  event_count INTEGER
);
CREATE INDEX dash_runs_batch ON dash_runs(batch_id);
CREATE INDEX dash_runs_experiment ON dash_runs(experiment_id);
CREATE INDEX dash_runs_status ON dash_runs(status);
CREATE TABLE dash_events (
  run_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  t REAL NOT NULL,
  iteration INTEGER NOT NULL,
  layer TEXT NOT NULL,
  kind TEXT NOT NULL,
  change TEXT NOT NULL,
  arc_type TEXT,
  element_id INTEGER NOT NULL,
  head TEXT,
  tail TEXT,
  label TEXT,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;
CREATE TABLE dash_constraints (
  run_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  t REAL NOT NULL,
  iteration INTEGER NOT NULL,
  kind TEXT NOT NULL,
  action TEXT NOT NULL,
  constraint_id INTEGER NOT NULL,
  content TEXT,
  vertices TEXT,
  conflict TEXT,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;
CREATE TABLE dash_expansions (
  run_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  t REAL NOT NULL,
  iteration INTEGER NOT NULL,
  object_id INTEGER NOT NULL,
  object_label TEXT,
  added TEXT,
  reason TEXT,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;
CREATE TABLE dash_phases (
  run_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  iteration INTEGER NOT NULL,
  phase TEXT NOT NULL,
  t_start REAL NOT NULL,
  t_end REAL NOT NULL,
  duration REAL NOT NULL,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;
CREATE TABLE dash_counters (
  run_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  t REAL NOT NULL,
  iteration INTEGER NOT NULL,
  name TEXT NOT NULL,
  value INTEGER NOT NULL,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;
CREATE TABLE dash_progress (
  run_id INTEGER NOT NULL,
  t REAL NOT NULL,
  iteration INTEGER NOT NULL,
  task_vertices INTEGER NOT NULL,
  task_hyperarcs INTEGER NOT NULL,
  task_extended_vertices INTEGER NOT NULL,
  task_extended_hyperarcs INTEGER NOT NULL,
  motion_vertices INTEGER NOT NULL,
  motion_hyperarcs INTEGER NOT NULL,
  motion_extended_vertices INTEGER NOT NULL,
  motion_extended_hyperarcs INTEGER NOT NULL,
  roadmap_vertices INTEGER NOT NULL,
  roadmap_edges INTEGER NOT NULL,
  constraints INTEGER NOT NULL,
  collision_checks INTEGER NOT NULL,
  PRIMARY KEY (run_id, t)
) WITHOUT ROWID;
CREATE TABLE enums (
  name VARCHAR(512),
  value INTEGER,
  description TEXT,
  PRIMARY KEY (name, value)
);
INSERT INTO enums VALUES ('status', 0, 'running'), ('status', 4, 'timeout'), ('status', 6, 'solved'),
  ('status', 7, 'crashed'), ('status', 8, 'cancelled'), ('status', 9, 'infeasible');
)sql";

void execOrFail(sqlite3* db, const std::string& sql) {
  char* error = nullptr;
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error), SQLITE_OK) << (error ? error : "");
}

// A version-1 file with one finished run and a few events, written without ResultsDb.
void writeVersion1File(const std::string& path) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  execOrFail(db, kFrozenV1);
  execOrFail(db, R"sql(
    INSERT INTO dash_experiments (id, family, params, version) VALUES (1, 'sorting', '{"objects":4,"robots":2}', '0.0.9');
    INSERT INTO dash_planner_configs (id, name, planner, settings) VALUES (1, 'lazy-dash', 'lazy-dash', '{}');
    INSERT INTO dash_runs (id, uuid, experiment_id, planner_config_id, family, params, seed, planner,
      planner_settings, code_version, host, start_time, end_time, status, total_time, task_vertices,
      task_hyperarcs, task_extended_vertices, task_extended_hyperarcs, motion_vertices, motion_hyperarcs,
      motion_extended_vertices, motion_extended_hyperarcs, event_count)
      VALUES (1, 'old-run-0001', 1, 1, 'sorting', '{"objects":4,"robots":2}', 7, 'lazy-dash', '{}', '0.0.9', 'old-host',
      '2025-01-01T00:00:00.000Z', '2025-01-01T00:00:02.000Z', 'solved', 2.0, 2, 1, 0, 0, 0, 0, 0, 0, 3);
    INSERT INTO dash_events VALUES (1, 0, 0.1, 0, 'task', 'vertex', 'added', NULL, 0, NULL, NULL, 'R1');
    INSERT INTO dash_events VALUES (1, 1, 0.2, 0, 'task', 'vertex', 'added', NULL, 1, NULL, NULL, 'O1');
    INSERT INTO dash_events VALUES (1, 2, 0.3, 1, 'task', 'hyperarc', 'added', 'pick', 0, '[2]', '[0,1]', 'pick');
    PRAGMA application_id = 1147229000;
    PRAGMA user_version = 1;
  )sql");
  sqlite3_close(db);
}

void setUserVersion(const std::string& path, int version, const std::string& extra_sql = "") {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  execOrFail(db, extra_sql + "PRAGMA user_version = " + std::to_string(version) + ";");
  sqlite3_close(db);
}

TEST(Schema, ANewFileGetsTheCurrentVersion) {
  testing::TempDir dir;
  ResultsDb db(dir.file("new.db"));
  EXPECT_EQ(db.schemaVersion(), kSchemaVersion);
  EXPECT_EQ(db.select("PRAGMA application_id").rows.at(0).at(0), SqlValue(std::int64_t{kApplicationId}));
  EXPECT_EQ(db.select("PRAGMA journal_mode").rows.at(0).at(0), SqlValue(std::string("wal")));
}

TEST(Schema, AVersion1FileIsMigratedAndKeepsItsRuns) {
  testing::TempDir dir;
  const std::string path = dir.file("v1.db");
  writeVersion1File(path);
  ASSERT_EQ(kApplicationId, 1147229000);  // the literal in the frozen file above

  // Read-only cannot migrate: it says so.
  try {
    ResultsDb ro(path, OpenMode::ReadOnly);
    FAIL() << "a read-only open of an older file should be refused";
  } catch (const SchemaError& e) {
    EXPECT_NE(std::string(e.what()).find("schema version 1 is older"), std::string::npos) << e.what();
  }

  ResultsDb db(path);
  EXPECT_EQ(db.schemaVersion(), kSchemaVersion);
  const auto old = db.getRun("old-run-0001");
  ASSERT_TRUE(old.has_value());
  EXPECT_EQ(old->status, RunStatus::Solved);
  EXPECT_EQ(old->meta.seed, 7u);
  EXPECT_EQ(old->event_count, 3);
  EXPECT_EQ(old->summary.sizes->vertices[0], 2);
  // Version 4 moved the events into dash_repr_events (codes); the view shows them as they were.
  const SqlRows events = db.select("SELECT seq, t, iteration, layer, kind, change, arc_type, element_id, head, tail, "
                                   "label FROM dash_events WHERE run_id = 1 ORDER BY seq");
  ASSERT_EQ(events.rows.size(), 3u);
  EXPECT_EQ(events.rows[2], (std::vector<SqlValue>{std::int64_t{2}, 0.3, std::int64_t{1}, std::string("task"),
                                                   std::string("hyperarc"), std::string("added"), std::string("pick"),
                                                   std::int64_t{0}, std::string("[2]"), std::string("[0,1]"),
                                                   std::string("pick")}));
  EXPECT_EQ(events.rows[0][10], SqlValue(std::string("R1")));
  EXPECT_EQ(events.rows[0][6], SqlValue());  // a vertex has no arc type
  EXPECT_EQ(db.select("SELECT layer, kind, change FROM dash_repr_events WHERE run_id = 1 AND seq = 2").rows.at(0),
            (std::vector<SqlValue>{std::int64_t{0}, std::int64_t{1}, std::int64_t{0}}));
  EXPECT_EQ(db.select("SELECT type FROM sqlite_schema WHERE name = 'dash_events'").rows.at(0).at(0),
            SqlValue(std::string("view")));
  EXPECT_EQ(db.select("SELECT COUNT(*) FROM dash_timeline WHERE run_id = 1").rows.at(0).at(0),
            SqlValue(std::int64_t{3}));
  EXPECT_FALSE(old->summary.exit_signal.has_value());
  // Version 7: a run stored before one phase accounting keeps its meaning (total = its wall time) and
  // says so: no accounting mark, no separate wall time.
  EXPECT_FALSE(old->summary.phase_accounting.has_value());
  EXPECT_FALSE(old->summary.wall_time.has_value());
  // Version 2's additions work on the migrated file.
  db.addTag("old-run-0001", "baseline");
  db.setNote("old-run-0001", "from 2025");
  const auto tagged = db.getRun("old-run-0001");
  EXPECT_EQ(tagged->tags, std::vector<std::string>{"baseline"});
  EXPECT_EQ(tagged->note, "from 2025");
  const std::string uuid = db.beginRun(testing::sampleMeta());
  db.finishRun(uuid, RunSummary{.status = RunStatus::Crashed, .exit_signal = 11});
  EXPECT_EQ(db.getRun(uuid)->summary.exit_signal, 11);
  // Planner Arena sees both runs.
  EXPECT_EQ(db.select("SELECT COUNT(*) FROM runs").rows.at(0).at(0), SqlValue(std::int64_t{2}));
}

// Version 3 added the dispatch history. A version-2 file (version 3's tables dropped) opens, migrates,
// keeps its runs, and records dispatches.
TEST(Schema, AVersion2FileGetsTheDispatchHistory) {
  testing::TempDir dir;
  const std::string path = dir.file("v2.db");
  std::string uuid;
  {
    ResultsDb db(path);
    uuid = db.beginRun(testing::sampleMeta());
    db.finishRun(uuid, RunSummary{.status = RunStatus::Solved});
  }
  setUserVersion(path, 2, "DROP TABLE dash_dispatch_arms; DROP TABLE dash_dispatches;");
  EXPECT_THROW(DispatchStore(path, OpenMode::ReadOnly), SchemaError);  // read-only cannot migrate

  DispatchStore store(path);
  {
    const ResultsDb db(path, OpenMode::ReadOnly);
    EXPECT_EQ(db.schemaVersion(), kSchemaVersion);
    EXPECT_EQ(db.getRun(uuid)->status, RunStatus::Solved);
  }
  DispatchRecord r;
  r.id = "d1-1";
  r.created = isoTimeFromUnixMillis(1767225600123);  // 2026-01-01
  r.state = "running";
  r.run_uuid = uuid;
  r.requested_by = "alice";
  r.client = "127.0.0.1";
  r.arms = {{.robot = "ur5e_0", .driver = "ur", .status = "executing", .result = "SUCCESSFUL"},
            {.robot = "ur5e_1", .driver = "sim", .status = "executing", .result = "SUCCESSFUL"}};
  store.save(r);
  // The end replaces the record: state, reason, per-arm results.
  r.state = "aborted";
  r.ended = isoTimeFromUnixMillis(1767225605000);
  r.reason = "ur5e_1 deviated 0.2 from the plan";
  r.arms[0].result = "CANCELLED";
  r.arms[0].result_code = -10;
  r.arms[1].result = "PATH_TOLERANCE_VIOLATED";
  r.arms[1].result_code = -4;
  r.arms[1].max_deviation = 0.2;
  store.save(r);
  DispatchRecord refused{.id = "d2-2", .created = isoTimeFromUnixMillis(1767225700000), .state = "refused",
                         .reason = "ur5e_1: the arm is not at the plan's start"};
  refused.arms = {{.robot = "ur5e_1"}};
  store.save(refused);

  const DispatchStore reader(path, OpenMode::ReadOnly);
  EXPECT_EQ(reader.count(), 2);
  const auto list = reader.list();
  ASSERT_EQ(list.size(), 2u);
  EXPECT_EQ(list[0].id, "d2-2");  // newest first
  EXPECT_EQ(list[0].arms.at(0).result, "");
  const DispatchRecord& back = list[1];
  EXPECT_EQ(back.created, "2026-01-01T00:00:00.123Z");
  EXPECT_EQ(back.ended, "2026-01-01T00:00:05.000Z");
  EXPECT_EQ(back.started, "");
  EXPECT_EQ(back.state, "aborted");
  EXPECT_EQ(back.reason, "ur5e_1 deviated 0.2 from the plan");
  EXPECT_EQ(back.run_uuid, uuid);
  EXPECT_EQ(back.requested_by, "alice");
  ASSERT_EQ(back.arms.size(), 2u);  // replaced, not doubled, in their order
  EXPECT_EQ(back.arms[0].robot, "ur5e_0");
  EXPECT_EQ(back.arms[0].result, "CANCELLED");
  EXPECT_EQ(back.arms[1].result_code, -4);
  EXPECT_DOUBLE_EQ(back.arms[1].max_deviation, 0.2);
  EXPECT_EQ(reader.list(1, 1).at(0).id, "d1-1");
  EXPECT_FALSE(reader.get("nope").has_value());
  EXPECT_THROW(DispatchStore(path, OpenMode::ReadOnly).save(r), InputError);
  EXPECT_EQ(testing::integrityCheck(path), "ok");
}

// Version 6 added a long phase's progress to the progress snapshots. A version-5 file (those columns
// dropped) migrates: its snapshots keep their sizes with NULL progress, and new runs record progress.
TEST(Schema, AVersion5FileGetsProgressColumnsInItsSnapshots) {
  testing::TempDir dir;
  const std::string path = dir.file("v5.db");
  std::string old_uuid;
  {
    ResultsDb db(path);
    old_uuid = db.beginRun(testing::sampleMeta());
    db.finishRun(old_uuid, RunSummary{.status = RunStatus::Solved});
  }
  setUserVersion(path, 5,
                 "ALTER TABLE dash_progress DROP COLUMN progress_phase; ALTER TABLE dash_progress DROP COLUMN "
                 "progress_done; ALTER TABLE dash_progress DROP COLUMN progress_total; ALTER TABLE dash_progress DROP "
                 "COLUMN progress_rate; ALTER TABLE dash_progress DROP COLUMN progress_current;");
  EXPECT_THROW(ResultsDb(path, OpenMode::ReadOnly), SchemaError);  // read-only cannot migrate

  ResultsDb db(path);
  EXPECT_EQ(db.schemaVersion(), kSchemaVersion);
  const SqlRows old = db.select("SELECT progress_phase, progress_done FROM dash_progress WHERE run_id = ?",
                                {db.getRun(old_uuid)->id});
  ASSERT_EQ(old.rows.size(), 1u);
  EXPECT_EQ(old.rows[0][0], SqlValue());
  EXPECT_EQ(old.rows[0][1], SqlValue());
  const std::string uuid = db.beginRun(testing::sampleMeta());
  {
    auto recorder = db.recorder(uuid);
    recorder->onEvent(Event{0.5, 1, ProgressEvent{Phase::ConflictResolution, 2, 9, 4.0, "ur5e_1"}});
  }
  db.finishRun(uuid, RunSummary{.status = RunStatus::Timeout});
  const SqlRows now = db.select("SELECT progress_phase, progress_done, progress_total, progress_current FROM "
                                "dash_progress WHERE run_id = ? ORDER BY t",
                                {db.getRun(uuid)->id});
  ASSERT_FALSE(now.rows.empty());
  EXPECT_EQ(now.rows.back(), (std::vector<SqlValue>{std::string("conflict_resolution"), std::int64_t{2},
                                                     std::int64_t{9}, std::string("ur5e_1")}));
  EXPECT_EQ(testing::integrityCheck(path), "ok");
}

// Version 8 added how a dispatch ran and each step's times. A version-7 file (those columns dropped)
// migrates: its dispatches stay, read as timed with no steps, and new records keep both.
TEST(Schema, AVersion7FileKeepsItsDispatchesAndGetsExecutionAndSegments) {
  testing::TempDir dir;
  const std::string path = dir.file("v7.db");
  DispatchRecord old{.id = "d1-7", .created = isoTimeFromUnixMillis(1767225600000), .state = "succeeded"};
  old.arms = {{.robot = "ur5e_0", .driver = "sim", .status = "succeeded", .result = "SUCCESSFUL", .samples = 42}};
  { DispatchStore(path).save(old); }
  setUserVersion(path, 7,
                 "ALTER TABLE dash_dispatches DROP COLUMN execution; ALTER TABLE dash_dispatch_arms DROP COLUMN "
                 "segments;");
  EXPECT_THROW(DispatchStore(path, OpenMode::ReadOnly), SchemaError);  // read-only cannot migrate

  DispatchStore store(path);
  EXPECT_EQ(ResultsDb(path, OpenMode::ReadOnly).schemaVersion(), kSchemaVersion);
  const auto back = store.get("d1-7");
  ASSERT_TRUE(back.has_value());
  EXPECT_EQ(back->state, "succeeded");
  EXPECT_EQ(back->execution, "timed");
  ASSERT_EQ(back->arms.size(), 1u);
  EXPECT_EQ(back->arms[0].samples, 42);
  EXPECT_EQ(back->arms[0].segments, "");
  DispatchRecord tpg{.id = "d1-8", .created = isoTimeFromUnixMillis(1767225700000), .state = "succeeded"};
  tpg.execution = "tpg";
  tpg.arms = {{.robot = "ur5e_0", .segments = R"([{"node":0,"kind":"motion","planned":[0,1],"executed":[0,1.2]}])"}};
  store.save(tpg);
  const auto saved = store.get("d1-8");
  ASSERT_TRUE(saved.has_value());
  EXPECT_EQ(saved->execution, "tpg");
  EXPECT_EQ(saved->arms.at(0).segments, tpg.arms[0].segments);
  EXPECT_EQ(store.count(), 2);
  EXPECT_EQ(testing::integrityCheck(path), "ok");
}

TEST(Schema, ANewerVersionGivesAClearError) {
  testing::TempDir dir;
  const std::string path = dir.file("future.db");
  { ResultsDb db(path); }
  setUserVersion(path, kSchemaVersion + 1);
  const std::string expected = "database schema version " + std::to_string(kSchemaVersion + 1) +
                               " is newer than this dashbench (" +
                               std::to_string(kSchemaVersion) + "); upgrade dashbench";
  for (OpenMode mode : {OpenMode::ReadWrite, OpenMode::ReadOnly}) {
    try {
      ResultsDb db(path, mode);
      FAIL() << "a newer file should be refused";
    } catch (const SchemaError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  EXPECT_EQ(testing::integrityCheck(path), "ok");
}

TEST(Schema, AForeignFileIsRefusedAndLeftAlone) {
  testing::TempDir dir;
  const std::string path = dir.file("other.db");
  setUserVersion(path, 0, "CREATE TABLE experiments (id INTEGER PRIMARY KEY, name TEXT);");
  EXPECT_THROW(ResultsDb db(path), SchemaError);
  sqlite3* raw = nullptr;
  sqlite3_open(path.c_str(), &raw);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(raw, "SELECT COUNT(*) FROM sqlite_schema", -1, &st, nullptr);
  sqlite3_step(st);
  EXPECT_EQ(sqlite3_column_int(st, 0), 1);  // nothing was added
  sqlite3_finalize(st);
  sqlite3_close(raw);
}

}  // namespace
}  // namespace dash::log
