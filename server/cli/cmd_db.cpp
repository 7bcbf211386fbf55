// dashbench db query|export|merge|info: the results database from the command line. The logic
// lives in engine/log (db_query.h, db_tools.h) so that the server serves the same answers.
#include <cstdio>
#include <fstream>
#include <string>

#include "engine/core/text_split.h"
#include "engine/log/db_query.h"
#include "engine/log/db_tools.h"
#include "engine/log/results_db.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kDbHelp;
const char* const kDbHelp =
    "usage: dashbench db SUBCOMMAND ...\n"
    "The results database (SQLite; also loads in Planner Arena).\n\n"
    "  db query FILE \"SQL\" [--format table|csv|json] [--max-rows N] [--timeout SEC]\n"
    "      Runs one read-only SQL statement. Writes, ATTACH/DETACH, transaction control and PRAGMAs\n"
    "      that change settings are refused (read-only PRAGMAs such as table_info are allowed).\n"
    "      Defaults: --format table, --max-rows 1000, --timeout 10.\n"
    "  db export FILE --format csv|json [--runs UUID,UUID,...] [--events] [--out PATH]\n"
    "      Runs (all, or the listed ones) as CSV or JSON; --events adds each run's events (JSON).\n"
    "  db merge OUT IN...\n"
    "      Adds the runs of each IN to OUT (created if missing), by run uuid, and the dispatch\n"
    "      records, by dispatch id: never twice.\n"
    "  db info FILE\n"
    "      Schema version, runs by status, table sizes (migrates an older file).\n\n"
    "Tables: dash_runs, dash_repr_events, dash_constraints, dash_expansions, dash_phases, dash_counters,\n"
    "dash_progress, dash_batches, dash_run_tags, dash_dispatches, dash_dispatch_arms; views: dash_events\n"
    "(dash_repr_events with names), dash_timeline and Planner Arena's experiments, plannerConfigs, runs,\n"
    "progress (and the enums table).\n";

namespace {

void writeOutput(const std::string& text, const std::optional<std::string>& out_path) {
  if (!out_path) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  std::ofstream out(*out_path, std::ios::binary);
  DASH_THROW_UNLESS(out.good(), "cannot write " + *out_path);
  out << text;
}

int runQuery(const std::vector<std::string>& words) {
  Args args(words, {.options = {"format", "max-rows", "timeout"}, .flags = {}});
  const auto& pos = args.positional();
  DASH_THROW_UNLESS(pos.size() == 2, "usage: dashbench db query FILE \"SQL\" [--format table|csv|json]");
  const log::OutputFormat format = log::parseOutputFormat(args.get("format", "table"));
  const log::QueryLimits limits{.max_rows = args.integer("max-rows", 1000), .timeout_seconds = args.number("timeout", 10.0)};
  const log::SqlRows rows = log::runReadOnlyQuery(pos[0], pos[1], limits);
  writeOutput(log::formatRows(rows, format), std::nullopt);
  if (rows.truncated && format != log::OutputFormat::Table) {
    std::fprintf(stderr, "dashbench db query: stopped at %lld rows (the row limit; see --max-rows)\n",
                 static_cast<long long>(limits.max_rows));
  }
  return kExitOk;
}

int runExport(const std::vector<std::string>& words) {
  Args args(words, {.options = {"format", "runs", "out"}, .flags = {"events"}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "usage: dashbench db export FILE --format csv|json [--runs UUID,...]");
  log::ExportOptions options{.format = log::parseOutputFormat(args.require("format")),
                             .uuids = splitList(args.get("runs", ""), ',', EmptyItems::kDrop),
                             .with_events = args.has("events")};
  const log::ResultsDb db(args.positional()[0], log::OpenMode::ReadOnly);
  writeOutput(log::exportRuns(db, options), args.get("out"));
  return kExitOk;
}

int runMerge(const std::vector<std::string>& words) {
  Args args(words, {});
  const auto& pos = args.positional();
  DASH_THROW_UNLESS(pos.size() >= 2, "usage: dashbench db merge OUT IN...");
  const log::MergeReport r = log::mergeDatabases(pos[0], {pos.begin() + 1, pos.end()});
  std::printf("%s: %lld runs added, %lld replaced (were running), %lld already present\n", pos[0].c_str(),
              static_cast<long long>(r.added), static_cast<long long>(r.replaced), static_cast<long long>(r.skipped));
  std::printf("%s: %lld dispatches added, %lld replaced (were active), %lld already present\n", pos[0].c_str(),
              static_cast<long long>(r.dispatches_added), static_cast<long long>(r.dispatches_replaced),
              static_cast<long long>(r.dispatches_skipped));
  return kExitOk;
}

int runInfo(const std::vector<std::string>& words) {
  Args args(words, {});
  DASH_THROW_UNLESS(args.positional().size() == 1, "usage: dashbench db info FILE");
  const log::ResultsDb db(args.positional()[0]);
  const std::string text = log::formatInfo(db.info());
  std::fwrite(text.data(), 1, text.size(), stdout);
  return kExitOk;
}

}  // namespace

int runDb(const std::vector<std::string>& words) {
  DASH_THROW_UNLESS(!words.empty(), "usage: dashbench db query|export|merge|info ... (see --help)");
  const std::string sub = words.front();
  const std::vector<std::string> rest(words.begin() + 1, words.end());
  try {
    if (sub == "query") return runQuery(rest);
    if (sub == "export") return runExport(rest);
    if (sub == "merge") return runMerge(rest);
    if (sub == "info") return runInfo(rest);
  } catch (const log::DbError& e) {
    std::fprintf(stderr, "dashbench db %s: %s\n", sub.c_str(), e.what());
    return kExitProblems;
  }
  throw InputError("unknown db subcommand '" + sub + "' (query, export, merge or info)");
}

}  // namespace dash::cli
