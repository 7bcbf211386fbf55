#include "engine/log/arena_views.h"

#include <sqlite3.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "engine/log/sqlite_util.h"

namespace dash::log {
namespace {

// Planner Arena reads column names with '_' shown as ' ', and SQLite compares names without case:
// two names that agree after both are the same column to it.
std::string normalized(std::string name) {
  for (char& c : name) c = c == '_' ? ' ' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return name;
}

const std::set<std::string>& reservedNames() {
  static const std::set<std::string> names = [] {
    std::set<std::string> s;
    for (const char* n : {"id", "name", "totaltime", "timelimit", "memorylimit", "runcount", "version", "hostname",
                          "cpuinfo", "date", "seed", "setup", "experiment", "planner", "experimentid", "plannerid",
                          "runid", "settings"}) {
      s.insert(normalized(n));
    }
    for (const std::string& a : arenaRunAttributes()) s.insert(normalized(a));
    return s;
  }();
  return names;
}

// Each attribute: the view's column name and its expression over dash_runs r.
struct Column {
  const char* name;
  const char* expr;
};

constexpr Column kRunColumns[] = {
    {"time", "r.total_time"},
    {"memory", "r.peak_memory"},
    {"solved", "(r.status = 'solved')"},
    {"status", "CASE r.status WHEN 'timeout' THEN 4 WHEN 'solved' THEN 6 WHEN 'crashed' THEN 7 "
               "WHEN 'cancelled' THEN 8 WHEN 'infeasible' THEN 9 ELSE 0 END"},
    {"iterations", "r.iterations"},
    {"time_task_construction", "r.time_task_construction"},
    {"time_task_query", "r.time_task_query"},
    {"time_task_conflict_detection", "r.time_task_conflict_detection"},
    {"time_motion_construction", "r.time_motion_construction"},
    {"time_motion_query", "r.time_motion_query"},
    {"time_conflict_resolution", "r.time_conflict_resolution"},
    {"time_validation", "r.time_validation"},
    {"time_other", "r.time_other"},
    {"task_vertices", "r.task_vertices"},
    {"task_hyperarcs", "r.task_hyperarcs"},
    {"task_extended_vertices", "r.task_extended_vertices"},
    {"task_extended_hyperarcs", "r.task_extended_hyperarcs"},
    {"motion_vertices", "r.motion_vertices"},
    {"motion_hyperarcs", "r.motion_hyperarcs"},
    {"motion_extended_vertices", "r.motion_extended_vertices"},
    {"motion_extended_hyperarcs", "r.motion_extended_hyperarcs"},
    {"roadmap_vertices", "r.roadmap_vertices"},
    {"roadmap_edges", "r.roadmap_edges"},
    {"constraints_frontier", "r.constraints_frontier"},
    {"constraints_history", "r.constraints_history"},
    {"constraints_motion", "r.constraints_motion"},
    {"constraints_interaction", "r.constraints_interaction"},
    {"task_space_expansions", "r.task_space_expansions"},
    {"collision_checks", "r.collision_checks"},
    {"collision_checks_eager", "r.collision_checks_eager"},
    {"collision_checks_lazy", "r.collision_checks_lazy"},
    {"makespan", "r.makespan"},
    {"path_length", "r.path_length"},
};

std::string runsView() {
  std::string sql = "CREATE VIEW runs AS SELECT r.id AS id, r.experiment_id AS experimentid, r.planner_config_id AS plannerid";
  for (const Column& c : kRunColumns) sql += std::string(", ") + c.expr + " AS " + c.name;
  return sql + " FROM dash_runs r WHERE r.status <> 'running'";
}

std::string experimentsView(sqlite3* db) {
  std::string sql =
      "CREATE VIEW experiments AS SELECT e.id AS id, e.family AS name, COALESCE(a.totaltime, 0.0) AS totaltime, "
      "a.timelimit AS timelimit, a.memorylimit AS memorylimit, COALESCE(rc.runcount, 0) AS runcount, "
      "'dashbench ' || e.version AS version, a.hostname AS hostname, a.cpuinfo AS cpuinfo, a.date AS date, "
      "CAST(a.seed AS TEXT) AS seed, e.family || ' ' || e.params AS setup";
  // One column per parameter name seen in any experiment, in name order.
  std::set<std::string> used = reservedNames();
  sql::Statement names(db, "SELECT DISTINCT j.key FROM dash_experiments e, json_each(e.params) j ORDER BY j.key");
  while (names.step()) {
    const std::string key = names.columnText(0);
    std::string column = arenaParameterColumn(key);
    for (int n = 2; used.count(normalized(column)) != 0; ++n) column = arenaParameterColumn(key) + "_" + std::to_string(n);
    used.insert(normalized(column));
    std::string path = "$.\"" + key + "\"";  // keys are validated at beginRun: no quotes or backslashes
    sql += ", json_extract(e.params, '" + path + "') AS " + sql::quoteIdentifier(column);
  }
  sql +=
      " FROM dash_experiments e"
      " LEFT JOIN (SELECT experiment_id, SUM(total_time) AS totaltime, MAX(time_limit) AS timelimit,"
      " MAX(memory_limit) AS memorylimit, MAX(host) AS hostname, MAX(cpu_info) AS cpuinfo, MIN(start_time) AS date,"
      " MIN(seed) AS seed FROM dash_runs WHERE status <> 'running' GROUP BY experiment_id) a ON a.experiment_id = e.id"
      " LEFT JOIN (SELECT experiment_id, MAX(c) AS runcount FROM (SELECT experiment_id, COUNT(*) AS c FROM dash_runs"
      " WHERE status <> 'running' GROUP BY experiment_id, planner_config_id) GROUP BY experiment_id) rc"
      " ON rc.experiment_id = e.id";
  return sql;
}

constexpr const char* kPlannerConfigsView =
    "CREATE VIEW plannerConfigs AS SELECT id, name, settings FROM dash_planner_configs";

constexpr const char* kProgressView =
    "CREATE VIEW progress AS SELECT run_id AS runid, t AS time, iteration, task_vertices, task_hyperarcs, "
    "task_extended_vertices, task_extended_hyperarcs, motion_vertices, motion_hyperarcs, motion_extended_vertices, "
    "motion_extended_hyperarcs, roadmap_vertices, roadmap_edges, constraints, collision_checks FROM dash_progress";

// Representation events with their names (dash_repr_events stores the codes of events.h).
constexpr const char* kEventsView =
    "CREATE VIEW dash_events AS SELECT run_id, seq, t, iteration,"
    " CASE layer WHEN 0 THEN 'task' WHEN 1 THEN 'task_extended' WHEN 2 THEN 'motion' WHEN 3 THEN 'motion_extended'"
    " END AS layer, CASE kind WHEN 0 THEN 'vertex' WHEN 1 THEN 'hyperarc' END AS kind,"
    " CASE change WHEN 0 THEN 'added' WHEN 1 THEN 'removed' END AS change, arc_type, element_id, head, tail, label"
    " FROM dash_repr_events";

constexpr const char* kTimelineView =
    "CREATE VIEW dash_timeline AS"
    " SELECT run_id, seq, t, iteration, 'representation' AS type, layer || ' ' || kind ||"
    " CASE WHEN arc_type IS NULL OR arc_type = '' THEN '' ELSE ' ' || arc_type END ||"
    " CASE WHEN change = 'removed' THEN ' removed' ELSE '' END AS what, element_id AS id,"
    " COALESCE(label, '') || CASE WHEN kind = 'hyperarc' THEN ' tail=' || COALESCE(tail, '[]') ||"
    " ' head=' || COALESCE(head, '[]') ELSE '' END AS detail FROM dash_events"
    " UNION ALL SELECT run_id, seq, t, iteration, 'constraint', kind || ' ' || action, constraint_id,"
    " COALESCE(content, '') || ' vertices=' || COALESCE(vertices, '[]') ||"
    " CASE WHEN conflict IS NULL OR conflict = '' THEN '' ELSE ' conflict: ' || conflict END FROM dash_constraints"
    " UNION ALL SELECT run_id, seq, t, iteration, 'task_space_expansion', COALESCE(object_label, ''), object_id,"
    " COALESCE(added, '') || CASE WHEN reason IS NULL OR reason = '' THEN '' ELSE ' (' || reason || ')' END"
    " FROM dash_expansions"
    " UNION ALL SELECT run_id, seq, t_end, iteration, 'phase', phase, NULL, printf('%.6f s', duration) FROM dash_phases"
    " UNION ALL SELECT run_id, seq, t, iteration, 'counter', name, NULL, CAST(value AS TEXT) FROM dash_counters";

// Drops and recreates view `name` if its stored definition differs from `sql`.
void ensureView(sqlite3* db, const std::string& name, const std::string& sql) {
  sql::Statement current(db, "SELECT sql FROM sqlite_schema WHERE type = 'view' AND name = ?");
  current.bind(1, name);
  if (current.step() && current.columnText(0) == sql) return;
  sql::exec(db, "DROP VIEW IF EXISTS " + sql::quoteIdentifier(name));
  sql::exec(db, sql);
}

}  // namespace

const std::vector<std::string>& arenaRunAttributes() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> v;
    for (const Column& c : kRunColumns) v.emplace_back(c.name);
    return v;
  }();
  return names;
}

std::string arenaParameterColumn(const std::string& parameter) {
  return reservedNames().count(normalized(parameter)) != 0 ? "param_" + parameter : parameter;
}

void refreshArenaViews(sqlite3* db) {
  ensureView(db, "runs", runsView());
  ensureView(db, "experiments", experimentsView(db));
  ensureView(db, "plannerConfigs", kPlannerConfigsView);
  ensureView(db, "progress", kProgressView);
  ensureView(db, "dash_events", kEventsView);
  ensureView(db, "dash_timeline", kTimelineView);
}

}  // namespace dash::log
