#include "server/http/run_table.h"

#include <algorithm>
#include <cctype>

#include "engine/core/check.h"
#include "server/http/api_json.h"

namespace dash::http {

namespace {

bool safeParameterName(const std::string& name) {
  if (name.empty() || name.size() > 64) return false;
  return std::all_of(name.begin(), name.end(), [](char ch) {
    return std::isalnum(static_cast<unsigned char>(ch)) != 0 || ch == '_' || ch == '-' || ch == '.';
  });
}

std::vector<RunColumn> fixedColumns() {
  using T = ColumnType;
  std::vector<RunColumn> c = {
      {"uuid", "r.uuid", T::kText, "run uuid", "run", false},
      {"id", "r.id", T::kInteger, "run id (in this file)", "run", true},
      {"batch", "r.batch_id", T::kText, "batch", "run", false},
      {"family", "r.family", T::kText, "scenario family", "run", true},
      {"scene", "r.scene", T::kText, "scene", "run", false},
      {"seed", "r.seed", T::kInteger, "seed", "run", true},
      {"planner", "r.planner", T::kText, "planner", "run", true},
      {"config", "c.name", T::kText, "planner configuration", "run", true},
      {"settings", "r.planner_settings", T::kText, "planner settings (JSON)", "run", false},
      {"status", "r.status", T::kText, "status", "outcome", true},
      {"error", "r.error", T::kText, "error", "outcome", false},
      {"exit_signal", "r.exit_signal", T::kInteger, "exit signal", "outcome", false},
      {"start_time", "r.start_time", T::kText, "started (UTC)", "run", false},
      {"end_time", "r.end_time", T::kText, "ended (UTC)", "run", false},
      {"time_limit", "r.time_limit", T::kReal, "time limit (s)", "run", false},
      {"memory_limit", "r.memory_limit", T::kReal, "memory limit (MB)", "run", false},
      {"total_time", "r.total_time", T::kReal, "total time (s)", "time", true},
      {"wall_time", "r.wall_time", T::kReal, "wall time (s)", "time", false},
      {"time_task",
       "(COALESCE(r.time_task_construction,0) + COALESCE(r.time_task_query,0) + "
       "COALESCE(r.time_task_conflict_detection,0))",
       T::kReal, "task time (s)", "time", false},
      {"time_motion",
       "(COALESCE(r.time_motion_construction,0) + COALESCE(r.time_motion_query,0) + "
       "COALESCE(r.time_conflict_resolution,0))",
       T::kReal, "motion time (s)", "time", false},
      {"time_task_construction", "r.time_task_construction", T::kReal, "task construction (s)", "time", false},
      {"time_task_query", "r.time_task_query", T::kReal, "task query (s)", "time", false},
      {"time_task_conflict_detection", "r.time_task_conflict_detection", T::kReal, "task conflict detection (s)",
       "time", false},
      {"time_motion_construction", "r.time_motion_construction", T::kReal, "motion construction (s)", "time", false},
      {"time_motion_query", "r.time_motion_query", T::kReal, "motion query (s)", "time", false},
      {"time_conflict_resolution", "r.time_conflict_resolution", T::kReal, "conflict resolution (s)", "time", false},
      {"time_validation", "r.time_validation", T::kReal, "validation (s)", "time", false},
      {"time_other", "r.time_other", T::kReal, "other (s)", "time", false},
      {"iterations", "r.iterations", T::kInteger, "iterations", "count", false},
      {"task_vertices", "r.task_vertices", T::kInteger, "H_T vertices", "size", true},
      {"task_hyperarcs", "r.task_hyperarcs", T::kInteger, "H_T hyperarcs", "size", true},
      {"task_extended_vertices", "r.task_extended_vertices", T::kInteger, "H_TE vertices", "size", false},
      {"task_extended_hyperarcs", "r.task_extended_hyperarcs", T::kInteger, "H_TE hyperarcs", "size", false},
      {"motion_vertices", "r.motion_vertices", T::kInteger, "H_M vertices", "size", true},
      {"motion_hyperarcs", "r.motion_hyperarcs", T::kInteger, "H_M hyperarcs", "size", false},
      {"motion_extended_vertices", "r.motion_extended_vertices", T::kInteger, "H_ME vertices", "size", false},
      {"motion_extended_hyperarcs", "r.motion_extended_hyperarcs", T::kInteger, "H_ME hyperarcs", "size", false},
      {"roadmap_vertices", "r.roadmap_vertices", T::kInteger, "roadmap vertices", "size", false},
      {"roadmap_edges", "r.roadmap_edges", T::kInteger, "roadmap edges", "size", false},
      {"constraints_frontier", "r.constraints_frontier", T::kInteger, "frontier constraints", "count", false},
      {"constraints_history", "r.constraints_history", T::kInteger, "history constraints", "count", false},
      {"constraints_motion", "r.constraints_motion", T::kInteger, "motion constraints", "count", false},
      {"constraints_interaction", "r.constraints_interaction", T::kInteger, "interaction constraints", "count", false},
      {"task_space_expansions", "r.task_space_expansions", T::kInteger, "task space expansions", "count", false},
      {"collision_checks", "r.collision_checks", T::kInteger, "collision checks", "count", false},
      {"makespan", "r.makespan", T::kReal, "makespan (s)", "outcome", true},
      {"path_length", "r.path_length", T::kReal, "path length (rad)", "outcome", false},
      {"peak_memory", "r.peak_memory", T::kReal, "peak memory (MB)", "outcome", false},
      {"event_count", "r.event_count", T::kInteger, "events", "count", false},
      {"has_plan", "(r.plan IS NOT NULL)", T::kInteger, "has a plan", "outcome", false},
      {"code_version", "r.code_version", T::kText, "code version", "run", false},
      {"host", "r.host", T::kText, "host", "run", false},
      {"note", "r.note", T::kText, "note", "run", false},
      {"tags",
       "(SELECT group_concat(t.tag, ',') FROM (SELECT tag FROM dash_run_tags WHERE run_id = r.id ORDER BY tag) t)",
       T::kText, "tags", "run", true},
  };
  return c;
}

}  // namespace

std::string RunTable::parameterExpression(const std::string& name) {
  DASH_DEMAND(safeParameterName(name));
  return "json_extract(r.params, '$.\"" + name + "\"')";
}

RunTable::RunTable(const log::ResultsDb& db) : columns_(fixedColumns()) {
  const log::SqlRows rows =
      db.select("SELECT DISTINCT j.key FROM dash_experiments e, json_each(e.params) j ORDER BY j.key");
  const std::size_t insert_at = 6;  // after seed: parameters read best next to the scene
  std::vector<RunColumn> param_columns;
  for (const auto& row : rows.rows) {
    if (!std::holds_alternative<std::string>(row[0])) continue;
    const std::string name = std::get<std::string>(row[0]);
    if (!safeParameterName(name)) continue;
    params_.push_back(name);
    const std::string api_name = find(name) != nullptr ? "param_" + name : name;
    param_columns.push_back({api_name, parameterExpression(name), ColumnType::kInteger, name, "param", true});
  }
  columns_.insert(columns_.begin() + static_cast<std::ptrdiff_t>(insert_at), param_columns.begin(),
                  param_columns.end());
}

const RunColumn* RunTable::find(const std::string& name) const {
  for (const RunColumn& c : columns_) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

std::string RunTable::selectList(const std::vector<std::string>& names) const {
  std::string out;
  auto add = [&](const RunColumn& c) { out += (out.empty() ? "" : ", ") + c.sql + " AS \"" + c.name + "\""; };
  if (names.empty()) {
    for (const RunColumn& c : columns_) add(c);
    return out;
  }
  for (const std::string& n : names) {
    const RunColumn* c = find(n);
    DASH_THROW_UNLESS(c != nullptr, "unknown column '" + n + "'");
    add(*c);
  }
  return out;
}

const char* RunTable::fromClause() {
  return "dash_runs r LEFT JOIN dash_planner_configs c ON c.id = r.planner_config_id";
}

std::string RunTable::columnsJson() const {
  Json list = Json::array();
  for (const RunColumn& c : columns_) {
    const char* type = c.type == ColumnType::kText ? "text" : c.type == ColumnType::kInteger ? "integer" : "real";
    list.push_back({{"name", c.name}, {"label", c.label}, {"type", type}, {"group", c.group}, {"shown", c.shown}});
  }
  return jsonText(Json{{"columns", list}, {"parameters", params_}});
}

}  // namespace dash::http
