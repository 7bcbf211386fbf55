// ResultsDb's read side: runs, batches, counts, and trusted SELECTs.
#include <cctype>
#include <nlohmann/json.hpp>

#include "engine/core/text_split.h"
#include "engine/log/results_db.h"
#include "engine/log/results_db_impl.h"
#include "engine/log/results_schema.h"
#include "engine/log/series_name.h"
#include "engine/log/run_columns.h"

namespace dash::log {
namespace {

std::vector<std::string> splitTags(const std::string& joined) { return splitList(joined, '\x1f', EmptyItems::kKeep); }

}  // namespace

std::vector<RunRecord> ResultsDb::listRuns(const RunFilter& filter) const {
  std::string sql = std::string("SELECT ") + kRunSelectColumns + (filter.include_plan ? ", r.plan" : ", NULL") +
                    " FROM dash_runs r WHERE 1";
  std::vector<SqlValue> params;
  auto where = [&](const char* clause, SqlValue value) {
    sql += clause;
    params.push_back(std::move(value));
  };
  if (!filter.batch_id.empty()) where(" AND r.batch_id = ?", filter.batch_id);
  if (filter.status) where(" AND r.status = ?", std::string(toString(*filter.status)));
  if (!filter.family.empty()) where(" AND r.family = ?", filter.family);
  if (!filter.planner.empty()) where(" AND r.planner = ?", filter.planner);
  if (!filter.uuids.empty()) {
    sql += " AND r.uuid IN (";
    for (std::size_t i = 0; i < filter.uuids.size(); ++i) {
      sql += i == 0 ? "?" : ",?";
      params.emplace_back(filter.uuids[i]);
    }
    sql += ")";
  }
  sql += filter.newest_first ? " ORDER BY r.id DESC" : " ORDER BY r.id";
  where(" LIMIT ?", filter.limit);
  where(" OFFSET ?", filter.offset);

  std::lock_guard lock(impl_->mutex);
  sql::Statement st(impl_->db.get(), sql);
  for (std::size_t i = 0; i < params.size(); ++i) st.bind(static_cast<int>(i) + 1, params[i]);
  std::vector<RunRecord> runs;
  while (st.step()) {
    RunRecord r = readRunRecord(st);
    r.tags = splitTags(st.isNull(kRunSelectColumnCount - 1) ? "" : st.columnText(kRunSelectColumnCount - 1));
    if (filter.include_plan && !st.isNull(kRunSelectColumnCount)) r.summary.plan_json = st.columnText(kRunSelectColumnCount);
    runs.push_back(std::move(r));
  }
  return runs;
}

std::optional<RunRecord> ResultsDb::getRun(const std::string& uuid) const {
  auto runs = listRuns(RunFilter{.uuids = {uuid}, .limit = 1, .include_plan = true});
  if (runs.empty()) return std::nullopt;
  return std::move(runs.front());
}

std::vector<BatchRecord> ResultsDb::listBatches() const {
  std::lock_guard lock(impl_->mutex);
  sql::Statement st(impl_->db.get(), "SELECT id, name, spec, created, status FROM dash_batches ORDER BY created, id");
  std::vector<BatchRecord> out;
  while (st.step()) {
    out.push_back({st.columnText(0), st.columnText(1), st.columnText(2), st.columnText(3), st.columnText(4)});
  }
  return out;
}

DbInfo ResultsDb::info() const {
  std::lock_guard lock(impl_->mutex);
  sqlite3* db = impl_->db.get();
  DbInfo info;
  info.path = impl_->path;
  info.schema_version = readSchemaVersion(db);
  sql::Statement st(db, "SELECT status, COUNT(*) FROM dash_runs GROUP BY status ORDER BY status");
  while (st.step()) {
    info.runs_by_status[st.columnText(0)] = st.columnInt(1);
    info.runs += st.columnInt(1);
  }
  info.experiments = sql::selectInt(db, "SELECT COUNT(*) FROM dash_experiments");
  info.planner_configs = sql::selectInt(db, "SELECT COUNT(*) FROM dash_planner_configs");
  info.batches = sql::selectInt(db, "SELECT COUNT(*) FROM dash_batches");
  info.events = sql::selectInt(db,
                               "SELECT (SELECT COUNT(*) FROM dash_repr_events) + (SELECT COUNT(*) FROM dash_constraints) + "
                               "(SELECT COUNT(*) FROM dash_expansions) + (SELECT COUNT(*) FROM dash_phases) + "
                               "(SELECT COUNT(*) FROM dash_counters)");
  return info;
}

SqlRows ResultsDb::select(const std::string& sql, const std::vector<SqlValue>& params) const {
  std::lock_guard lock(impl_->mutex);
  return sql::selectRows(impl_->db.get(), sql, params);
}

std::string seriesName(const std::string& config, const std::string& settings_json) {
  const nlohmann::json settings = nlohmann::json::parse(settings_json, nullptr, false);
  if (!settings.is_object() || !settings.contains("profile") || !settings["profile"].is_string()) return config;
  const std::string profile = settings["profile"].get<std::string>();
  if (profile.empty()) return config;
  std::string word;
  for (std::size_t i = 0; i <= config.size(); ++i) {
    const char c = i < config.size() ? config[i] : ' ';
    if (std::isalnum(static_cast<unsigned char>(c)) || c == '_') {
      word += c;
      continue;
    }
    if (word == profile) return config;
    word.clear();
  }
  return config + " (" + profile + ")";
}

}  // namespace dash::log
