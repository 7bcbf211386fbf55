#pragma once
// Private to engine/log: how dash_runs columns map to RunRecord / RunSummary, and how a run's
// outcome is written (run_finish.cpp).
#include <optional>
#include <string>

#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

struct RunFigures;

/// `SET` list of finishRun's UPDATE, in the order finishLocked binds it.
extern const char* const kFinishAssignments;

/// Columns of dash_runs r read into a RunRecord (the last one is the tags, joined by '\x1f').
extern const char* const kRunSelectColumns;
extern const int kRunSelectColumnCount;

/// Reads one row selected with kRunSelectColumns (tags and plan are left to the caller).
RunRecord readRunRecord(const sql::Statement& st);

/// Now, as ISO 8601 UTC with milliseconds: "2026-11-21T13:21:05.123Z".
std::string isoNow();

/// The local id of run `uuid`; throws InputError if there is none.
std::int64_t runIdOf(sqlite3* db, const std::string& uuid);

/// Writes a run's outcome (status 'running' no more): `summary`, with every unset figure derived
/// from the run's stored events, plus a last progress row. `elapsed`: wall time since beginRun,
/// if this process began it. `figures`: the writer's tally of the events it stored for the run
/// (exactly what SQL over them would give, without reading them back), if it recorded every one;
/// nullptr: derive them with SQL. Caller holds the database mutex.
void finishRunLocked(ResultsDb::Impl& m, std::int64_t run_id, const RunSummary& summary,
                     std::optional<double> elapsed, const std::string& recorder_error,
                     const RunFigures* figures = nullptr);

}  // namespace dash::log
