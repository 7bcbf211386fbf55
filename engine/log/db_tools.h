#pragma once
// The logic of `dashbench db export|merge|info`, kept here so the server can reuse it.
#include <string>
#include <vector>

#include "engine/log/db_query.h"
#include "engine/log/results_db.h"

namespace dash::log {

struct ExportOptions {
  OutputFormat format = OutputFormat::Json;  ///< Csv or Json
  std::vector<std::string> uuids;            ///< empty: every run
  bool with_events = false;  ///< JSON only: each run's events, constraints, expansions, phases,
                             ///< counters and progress
};

/// Runs as CSV (one row per run, every dash_runs column but the plan) or JSON (an array of runs
/// with params, settings and plan as JSON values). Throws InputError for unknown uuids.
std::string exportRuns(const ResultsDb& db, const ExportOptions& options);

/// Merges each input into the file at `out_path` (created if missing); returns the totals.
MergeReport mergeDatabases(const std::string& out_path, const std::vector<std::string>& in_paths);

/// Schema version, runs by status, and table sizes, for people.
std::string formatInfo(const DbInfo& info);

}  // namespace dash::log
