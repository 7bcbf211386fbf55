#pragma once
// Private to engine/log: how dash_runs columns map to RunRecord / RunSummary, in one place.
#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

/// `SET` list of finishRun's UPDATE, in the order finishLocked binds it.
extern const char* const kFinishAssignments;

/// Columns of dash_runs r read into a RunRecord (the last one is the tags, joined by '\x1f').
extern const char* const kRunSelectColumns;
extern const int kRunSelectColumnCount;

/// Reads one row selected with kRunSelectColumns (tags and plan are left to the caller).
RunRecord readRunRecord(const sql::Statement& st);

}  // namespace dash::log
