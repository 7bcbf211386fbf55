#include "engine/log/db_tools.h"

#include <nlohmann/json.hpp>
#include <set>

#include "engine/core/check.h"

namespace dash::log {
namespace {

nlohmann::json toJson(const SqlValue& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return *i;
  if (const auto* d = std::get_if<double>(&v)) return std::isfinite(*d) ? nlohmann::json(*d) : nlohmann::json();
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  return nullptr;
}

// Columns that hold JSON text come out as JSON values.
const std::set<std::string>& jsonColumns() {
  static const std::set<std::string> names = {"params", "planner_settings", "plan", "head", "tail", "vertices"};
  return names;
}

nlohmann::json rowsToJson(const SqlRows& rows, std::size_t skip_columns) {
  nlohmann::json array = nlohmann::json::array();
  for (const auto& row : rows.rows) {
    nlohmann::json object = nlohmann::json::object();
    for (std::size_t c = skip_columns; c < row.size(); ++c) {
      nlohmann::json value = toJson(row[c]);
      if (value.is_string() && jsonColumns().count(rows.columns[c]) != 0) {
        value = nlohmann::json::parse(value.get<std::string>(), nullptr, false);
      }
      object[rows.columns[c]] = std::move(value);
    }
    array.push_back(std::move(object));
  }
  return array;
}

}  // namespace

std::string exportRuns(const ResultsDb& db, const ExportOptions& options) {
  DASH_THROW_UNLESS(options.format != OutputFormat::Table, "export writes csv or json");
  std::string sql = "SELECT r.*, (SELECT group_concat(tag, ',') FROM dash_run_tags WHERE run_id = r.id) AS tags "
                    "FROM dash_runs r";
  std::vector<SqlValue> params;
  if (!options.uuids.empty()) {
    sql += " WHERE r.uuid IN (";
    for (std::size_t i = 0; i < options.uuids.size(); ++i) {
      sql += i == 0 ? "?" : ",?";
      params.emplace_back(options.uuids[i]);
    }
    sql += ")";
  }
  SqlRows runs = db.select(sql + " ORDER BY r.id", params);
  if (!options.uuids.empty()) {
    std::set<std::string> found;
    const auto uuid_column = static_cast<std::size_t>(
        std::find(runs.columns.begin(), runs.columns.end(), "uuid") - runs.columns.begin());
    for (const auto& row : runs.rows) found.insert(std::get<std::string>(row[uuid_column]));
    for (const auto& uuid : options.uuids) DASH_THROW_UNLESS(found.count(uuid) != 0, "no run with uuid " + uuid);
  }

  if (options.format == OutputFormat::Csv) {
    DASH_THROW_UNLESS(!options.with_events, "--events needs --format json");
    const auto plan = std::find(runs.columns.begin(), runs.columns.end(), "plan") - runs.columns.begin();
    runs.columns.erase(runs.columns.begin() + plan);
    for (auto& row : runs.rows) row.erase(row.begin() + plan);
    return formatRows(runs, OutputFormat::Csv);
  }

  nlohmann::json out = rowsToJson(runs, 0);
  if (options.with_events) {
    static constexpr std::pair<const char*, const char*> kTables[] = {
        {"events", "dash_events"},   {"constraints", "dash_constraints"}, {"task_space_expansions", "dash_expansions"},
        {"phases", "dash_phases"},   {"counters", "dash_counters"},       {"progress", "dash_progress"}};
    for (auto& run : out) {
      const std::int64_t id = run["id"].get<std::int64_t>();
      for (const auto& [key, table] : kTables) {
        const std::string order = std::string(table) == "dash_progress" ? "t" : "seq";
        run[key] = rowsToJson(db.select(std::string("SELECT * FROM ") + table + " WHERE run_id = ? ORDER BY " + order, {id}), 1);
      }
    }
  }
  return out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

MergeReport mergeDatabases(const std::string& out_path, const std::vector<std::string>& in_paths) {
  DASH_THROW_UNLESS(!in_paths.empty(), "merge needs at least one input file");
  ResultsDb out(out_path);
  MergeReport total;
  for (const std::string& in : in_paths) {
    const MergeReport r = out.mergeFrom(in);
    total.added += r.added;
    total.replaced += r.replaced;
    total.skipped += r.skipped;
    total.dispatches_added += r.dispatches_added;
    total.dispatches_replaced += r.dispatches_replaced;
    total.dispatches_skipped += r.dispatches_skipped;
  }
  return total;
}

std::string formatInfo(const DbInfo& info) {
  std::string out = info.path + "\n";
  out += "  schema version   " + std::to_string(info.schema_version) + "\n";
  out += "  runs             " + std::to_string(info.runs) + "\n";
  for (const auto& [status, n] : info.runs_by_status) {
    out += "    " + status + std::string(status.size() < 14 ? 14 - status.size() : 1, ' ') + std::to_string(n) + "\n";
  }
  out += "  experiments      " + std::to_string(info.experiments) + "\n";
  out += "  planner configs  " + std::to_string(info.planner_configs) + "\n";
  out += "  batches          " + std::to_string(info.batches) + "\n";
  out += "  events           " + std::to_string(info.events) + "\n";
  return out;
}

}  // namespace dash::log
