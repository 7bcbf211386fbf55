#include "engine/log/results_schema.h"

#include <sqlite3.h>

#include <array>

#include "engine/log/sqlite_util.h"

namespace dash::log {
namespace {

// Version 1. Never edit a released migration: add a new one. tests/log/schema_test.cpp keeps a
// copy of this DDL to prove that version-1 files still open.
constexpr const char* kSchemaV1 = R"sql(
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

constexpr const char* kSchemaV2 = R"sql(
ALTER TABLE dash_runs ADD COLUMN exit_signal INTEGER;
ALTER TABLE dash_runs ADD COLUMN note TEXT;
CREATE TABLE dash_run_tags (
  run_id INTEGER NOT NULL,
  tag TEXT NOT NULL,
  PRIMARY KEY (run_id, tag)
) WITHOUT ROWID;
)sql";

// Every plan dispatched to arm controllers (server/dispatch): who asked, when, how it ended, and
// each arm's result. Times are ISO-8601 UTC text like dash_runs'; `dispatch_id` is the service's id.
// IF NOT EXISTS: a file made to look older by dropping only version 2's additions (the merge tests
// do) still migrates.
constexpr const char* kSchemaV3 = R"sql(
CREATE TABLE IF NOT EXISTS dash_dispatches (
  id TEXT PRIMARY KEY,
  created TEXT NOT NULL,
  started TEXT,
  ended TEXT,
  state TEXT NOT NULL,
  reason TEXT,
  run_uuid TEXT,
  scene TEXT,
  planner TEXT,
  requested_by TEXT,
  client TEXT,
  time_scale REAL,
  duration REAL,
  elapsed REAL,
  preflight TEXT
);
CREATE INDEX IF NOT EXISTS dash_dispatches_created ON dash_dispatches(created);
CREATE TABLE IF NOT EXISTS dash_dispatch_arms (
  dispatch_id TEXT NOT NULL,
  robot TEXT NOT NULL,
  ordinal INTEGER NOT NULL,
  driver TEXT,
  status TEXT,
  result TEXT NOT NULL,
  result_code INTEGER,
  message TEXT,
  duration REAL,
  max_deviation REAL,
  samples INTEGER,
  PRIMARY KEY (dispatch_id, robot)
) WITHOUT ROWID;
)sql";

// Representation events, the bulk of every run, with their layer, kind and change as small
// integers (the codes of events.h: layer 0 task, 1 task_extended, 2 motion, 3 motion_extended;
// kind 0 vertex, 1 hyperarc; change 0 added, 1 removed) instead of text: a sixth less to store and
// write per event. The view dash_events (arena_views.cpp) shows them with the names, as version 3's
// table did. IF NOT EXISTS, like version 3: a file made to look older still migrates.
constexpr const char* kSchemaV4 = R"sql(
CREATE TABLE IF NOT EXISTS dash_repr_events (
  run_id INTEGER NOT NULL,
  seq INTEGER NOT NULL,
  t REAL NOT NULL,
  iteration INTEGER NOT NULL,
  layer INTEGER NOT NULL,
  kind INTEGER NOT NULL,
  change INTEGER NOT NULL,
  arc_type TEXT,
  element_id INTEGER NOT NULL,
  head TEXT,
  tail TEXT,
  label TEXT,
  PRIMARY KEY (run_id, seq)
) WITHOUT ROWID;
)sql";

// Version 3's table, if there is one (a file made to look older may already have the view).
constexpr const char* kSchemaV4Copy = R"sql(
INSERT INTO dash_repr_events SELECT run_id, seq, t, iteration,
  CASE layer WHEN 'task' THEN 0 WHEN 'task_extended' THEN 1 WHEN 'motion' THEN 2 WHEN 'motion_extended' THEN 3 END,
  CASE kind WHEN 'vertex' THEN 0 WHEN 'hyperarc' THEN 1 END, CASE change WHEN 'added' THEN 0 WHEN 'removed' THEN 1 END,
  arc_type, element_id, head, tail, label FROM dash_events ORDER BY run_id, seq;
DROP VIEW IF EXISTS dash_timeline;
DROP TABLE dash_events;
)sql";

void migrateToV4(sqlite3* db) {
  sql::exec(db, kSchemaV4);
  if (sql::selectInt(db, "SELECT COUNT(*) FROM sqlite_schema WHERE type = 'table' AND name = 'dash_events'") > 0) {
    sql::exec(db, kSchemaV4Copy);
  }
}

// The planner's in-loop plan validation as a phase of its own (events.h Phase::Validation). Only when
// missing: a file made to look older (the merge and schema tests lower user_version) keeps its column.
constexpr const char* kSchemaV5 = R"sql(
ALTER TABLE dash_runs ADD COLUMN time_validation REAL;
)sql";

void migrateToV5(sqlite3* db) {
  if (sql::selectInt(db, "SELECT COUNT(*) FROM pragma_table_info('dash_runs') WHERE name = 'time_validation'") == 0)
    sql::exec(db, kSchemaV5);
}

// The latest progress of a long phase in every progress snapshot (events.h ProgressEvent): conflict
// resolution's task steps scheduled of the plan's, the step's robots, steps per second. NULL in the
// snapshots of older runs and before a run's first progress event. Only the columns missing: a file
// made to look older keeps its columns.
constexpr std::array<const char*, 5> kSchemaV6Columns = {"progress_phase TEXT", "progress_done INTEGER",
                                                         "progress_total INTEGER", "progress_rate REAL",
                                                         "progress_current TEXT"};

void migrateToV6(sqlite3* db) {
  for (const std::string column : kSchemaV6Columns) {
    const std::string name = column.substr(0, column.find(' '));
    if (sql::selectInt(db, "SELECT COUNT(*) FROM pragma_table_info('dash_progress') WHERE name = '" + name + "'") == 0)
      sql::exec(db, "ALTER TABLE dash_progress ADD COLUMN " + column);
  }
}

// One phase accounting for both planners (docs/planners.md "Phases"): total_time is the sum of the
// phases, wall_time the solve's wall time beside it, phase_accounting 2 marks such a row. Rows already
// stored keep their meaning (phase_accounting NULL: total_time was the wall time). Only the columns
// missing: a file made to look older keeps its columns.
constexpr std::array<const char*, 2> kSchemaV7Columns = {"wall_time REAL", "phase_accounting INTEGER"};

void migrateToV7(sqlite3* db) {
  for (const std::string column : kSchemaV7Columns) {
    const std::string name = column.substr(0, column.find(' '));
    if (sql::selectInt(db, "SELECT COUNT(*) FROM pragma_table_info('dash_runs') WHERE name = '" + name + "'") == 0)
      sql::exec(db, "ALTER TABLE dash_runs ADD COLUMN " + column);
  }
}

// Execution by dependencies (issue 39): how a dispatch ran, and per arm the planned and executed
// times of each step (JSON). NULL in older records. Only the columns missing, as v6 and v7.
void migrateToV8(sqlite3* db) {
  const std::array<std::pair<const char*, const char*>, 2> columns = {
      {{"dash_dispatches", "execution TEXT"}, {"dash_dispatch_arms", "segments TEXT"}}};
  for (const auto& [table, column] : columns) {
    const std::string name = std::string(column).substr(0, std::string(column).find(' '));
    if (sql::selectInt(db, std::string("SELECT COUNT(*) FROM pragma_table_info('") + table + "') WHERE name = '" + name +
                               "'") == 0)
      sql::exec(db, std::string("ALTER TABLE ") + table + " ADD COLUMN " + column);
  }
}

struct Migration {
  int to;  ///< the version after it
  void (*apply)(sqlite3* db);
};

// One entry per version, in order. A migration may transform data, not just run DDL.
constexpr std::array<Migration, kSchemaVersion> kMigrations = {{
    {1, [](sqlite3* db) { sql::exec(db, kSchemaV1); }},
    {2, [](sqlite3* db) { sql::exec(db, kSchemaV2); }},
    {3, [](sqlite3* db) { sql::exec(db, kSchemaV3); }},
    {4, migrateToV4},
    {5, migrateToV5},
    {6, migrateToV6},
    {7, migrateToV7},
    {8, migrateToV8},
}};

std::string newerMessage(int version) {
  return "database schema version " + std::to_string(version) + " is newer than this dashbench (" +
         std::to_string(kSchemaVersion) + "); upgrade dashbench";
}

void checkOurs(sqlite3* db, const std::string& path, int version) {
  const std::int64_t app = sql::selectInt(db, "PRAGMA application_id");
  const std::int64_t tables = sql::selectInt(db, "SELECT count(*) FROM sqlite_schema");
  if ((app != 0 && app != kApplicationId) || (version == 0 && tables > 0)) {
    throw SchemaError(path + " is not a dashbench results database (it has other tables and no dashbench "
                             "schema version)");
  }
}

}  // namespace

int readSchemaVersion(sqlite3* db) { return static_cast<int>(sql::selectInt(db, "PRAGMA user_version")); }

void migrateSchema(sqlite3* db, const std::string& path) {
  int version = readSchemaVersion(db);
  if (version > kSchemaVersion) throw SchemaError(path + ": " + newerMessage(version));
  if (version == kSchemaVersion) return;
  checkOurs(db, path, version);
  for (const Migration& m : kMigrations) {
    if (m.to <= version) continue;
    sql::exec(db, "BEGIN IMMEDIATE");
    try {
      // Re-read inside the write lock: another process may have migrated meanwhile.
      if (readSchemaVersion(db) >= m.to) {
        sql::exec(db, "COMMIT");
        version = m.to;
        continue;
      }
      m.apply(db);
      sql::exec(db, "PRAGMA application_id = " + std::to_string(kApplicationId));
      sql::exec(db, "PRAGMA user_version = " + std::to_string(m.to));
      sql::exec(db, "COMMIT");
    } catch (...) {
      sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
      throw;
    }
    version = m.to;
  }
}

void checkSchemaReadable(sqlite3* db, const std::string& path) {
  const int version = readSchemaVersion(db);
  if (version > kSchemaVersion) throw SchemaError(path + ": " + newerMessage(version));
  checkOurs(db, path, version);
  if (version < kSchemaVersion) {
    throw SchemaError(path + ": database schema version " + std::to_string(version) + " is older than this dashbench (" +
                      std::to_string(kSchemaVersion) + "); open it read-write once (e.g. `dashbench db info`) to migrate it");
  }
}

}  // namespace dash::log
