#pragma once
// The results database's schema: its version (PRAGMA user_version), the migrations that bring an
// older file up to date, and the checks that refuse a newer file or a file that is not ours.
//
// Tables are versioned; views are not: every view (Planner Arena's `experiments`, `plannerConfigs`,
// `runs`, `progress`, `dash_events` and `dash_timeline`) is derived and recreated by refreshArenaViews()
// (arena_views.h), so a migration only ever touches dash_* tables and `enums`.
//
// Version history:
//   1  dash_batches, dash_experiments, dash_planner_configs, dash_runs, dash_events,
//      dash_constraints, dash_expansions, dash_phases, dash_counters, dash_progress, enums
//   2  dash_runs.exit_signal, dash_runs.note, dash_run_tags (tags and notes per run)
//   3  dash_dispatches, dash_dispatch_arms (plans dispatched to arm controllers: dispatch_store.h)
//   4  dash_events becomes a view over dash_repr_events (layer, kind and change as integer codes)
//   5  dash_runs.time_validation
//   6  dash_progress.progress_phase, progress_done, progress_total, progress_rate, progress_current (how
//      far a long phase has got: conflict resolution's steps scheduled of the plan's)
//   7  dash_runs.wall_time, phase_accounting (one phase accounting for both planners)
//   8  dash_dispatches.execution ("timed" or "tpg"), dash_dispatch_arms.segments (execution by
//      dependencies: each step's planned and executed times, JSON)
#include <string>

#include "engine/core/check.h"

struct sqlite3;

namespace dash::log {

inline constexpr int kSchemaVersion = 8;
/// PRAGMA application_id of a dashbench results file ("DaSH").
inline constexpr int kApplicationId = 0x44615348;

/// The file cannot be used by this build: its schema is newer, or it is not a results database.
class SchemaError : public InputError {
 public:
  using InputError::InputError;
};

/// The version stored in the file (0 for a new, empty file).
int readSchemaVersion(sqlite3* db);

/// Brings a writable connection's schema to kSchemaVersion, one migration (one transaction) at a
/// time. Throws SchemaError for a newer version or a foreign file. `path` is for messages.
void migrateSchema(sqlite3* db, const std::string& path);

/// For read-only connections, which cannot migrate: throws SchemaError unless the file is at
/// exactly kSchemaVersion (an older file must be opened read-write once).
void checkSchemaReadable(sqlite3* db, const std::string& path);

}  // namespace dash::log
