#include "server/http/series_queries.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <optional>

#include "engine/log/results_db.h"
#include "engine/log/series_name.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/run_filter.h"
#include "server/http/run_table.h"

namespace dash::http {

namespace {

struct Metric {
  const char* name;
  const char* sql;
  const char* label;
  const char* unit;
};

const std::vector<Metric>& metrics() {
  static const std::vector<Metric> m = {
      {"task_vertices", "r.task_vertices", "H_T vertices", "count"},
      {"task_hyperarcs", "r.task_hyperarcs", "H_T hyperarcs", "count"},
      {"task_extended_vertices", "r.task_extended_vertices", "H_TE vertices", "count"},
      {"task_extended_hyperarcs", "r.task_extended_hyperarcs", "H_TE hyperarcs", "count"},
      {"motion_vertices", "r.motion_vertices", "H_M vertices", "count"},
      {"motion_hyperarcs", "r.motion_hyperarcs", "H_M hyperarcs", "count"},
      {"motion_extended_vertices", "r.motion_extended_vertices", "H_ME vertices", "count"},
      {"motion_extended_hyperarcs", "r.motion_extended_hyperarcs", "H_ME hyperarcs", "count"},
      {"time_task_construction", "r.time_task_construction", "task construction", "s"},
      {"time_task_query", "r.time_task_query", "task query", "s"},
      {"time_task_conflict_detection", "r.time_task_conflict_detection", "task conflict detection", "s"},
      {"time_motion_construction", "r.time_motion_construction", "motion construction", "s"},
      {"time_motion_query", "r.time_motion_query", "motion query", "s"},
      {"time_conflict_resolution", "r.time_conflict_resolution", "conflict resolution", "s"},
      {"time_validation", "r.time_validation", "validation", "s"},
      {"time_other", "r.time_other", "other", "s"},
      {"time_task",
       "(COALESCE(r.time_task_construction,0) + COALESCE(r.time_task_query,0) + "
       "COALESCE(r.time_task_conflict_detection,0))",
       "task total", "s"},
      {"time_motion",
       "(COALESCE(r.time_motion_construction,0) + COALESCE(r.time_motion_query,0) + "
       "COALESCE(r.time_conflict_resolution,0))",
       "motion total", "s"},
      {"total_time", "r.total_time", "total", "s"},
      {"makespan", "r.makespan", "makespan", "s"},
  };
  return m;
}

/// Linear interpolation between order statistics (type 7, as numpy and R's default).
double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - static_cast<double>(lo));
}

Json summary(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  Json j = {{"n", values.size()}, {"values", values}};
  if (values.empty()) {
    for (const char* k : {"median", "q1", "q3", "min", "max", "mean"}) j[k] = nullptr;
    return j;
  }
  j["median"] = quantile(values, 0.5);
  j["q1"] = quantile(values, 0.25);
  j["q3"] = quantile(values, 0.75);
  j["min"] = values.front();
  j["max"] = values.back();
  j["mean"] = std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
  return j;
}

std::optional<double> number(const log::SqlValue& v) {
  if (const auto* i = std::get_if<std::int64_t>(&v)) return static_cast<double>(*i);
  if (const auto* d = std::get_if<double>(&v)) return *d;
  return std::nullopt;
}

std::string text(const log::SqlValue& v) {
  if (const auto* s = std::get_if<std::string>(&v)) return *s;
  return "";
}

}  // namespace

std::string SeriesQueries::seriesJson(const SeriesRequest& request) const {
  if (request.family.empty()) throw HttpError(400, "family: required (e.g. family=sorting)");
  if (request.group_by != "config" && request.group_by != "planner") {
    throw HttpError(400, "group_by: '" + request.group_by + "' is not config or planner");
  }
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const RunTable table(db);
  const auto& params = table.parameterNames();
  if (std::find(params.begin(), params.end(), request.x) == params.end()) {
    std::string known;
    for (const auto& p : params) known += (known.empty() ? "" : ", ") + p;
    throw HttpError(400, "x: '" + request.x + "' is not a scenario parameter of any run (known: " + known + ")");
  }
  if (!request.split.empty() &&
      (request.split == request.x || std::find(params.begin(), params.end(), request.split) == params.end())) {
    throw HttpError(400, "split: '" + request.split + "' is not another scenario parameter");
  }
  SqlCondition where = parseRunFilter(request.filter, table);
  where.andWith("r.family = ?", {request.family});
  where.andWith("r.status NOT IN ('running', 'cancelled')");
  std::string sql = std::string("SELECT ") + (request.group_by == "config" ? "c.name" : "r.planner") + ", " +
                    RunTable::parameterExpression(request.x) + ", r.status, " +
                    (request.split.empty() ? std::string("NULL") : RunTable::parameterExpression(request.split)) +
                    ", r.planner_settings";
  for (const Metric& m : metrics()) sql += std::string(", ") + m.sql;
  sql += std::string(" FROM ") + RunTable::fromClause() + " WHERE " + where.sql;
  const log::SqlRows rows = db.select(sql, where.params);

  struct Group {
    std::map<std::string, std::int64_t> by_status;
    std::vector<std::vector<double>> values = std::vector<std::vector<double>>(metrics().size());
  };
  std::map<std::pair<std::string, double>, Group> groups;
  for (const auto& row : rows.rows) {
    const std::optional<double> x = number(row[1]);
    if (!x) continue;  // the run has no such parameter
    // Grouped by configuration, a configuration's two profiles are two series (log::seriesName).
    std::string name = request.group_by == "config" ? log::seriesName(text(row[0]), text(row[4])) : text(row[0]);
    if (const auto s = number(row[3]); s && !request.split.empty()) {
      name += " · " + request.split + "=" + std::to_string(static_cast<long long>(*s));
    }
    Group& g = groups[{name, *x}];
    const std::string status = text(row[2]);
    ++g.by_status[status];
    if (status != "solved" && !request.include_unsolved) continue;
    for (std::size_t m = 0; m < metrics().size(); ++m) {
      if (const auto v = number(row[5 + m])) g.values[m].push_back(*v);
    }
  }
  Json out_groups = Json::array();
  for (const auto& [key, g] : groups) {
    std::int64_t finished = 0;
    for (const auto& [s, n] : g.by_status) finished += n;
    const std::int64_t solved = g.by_status.count("solved") != 0 ? g.by_status.at("solved") : 0;
    Json m = Json::object();
    for (std::size_t i = 0; i < metrics().size(); ++i) m[metrics()[i].name] = summary(g.values[i]);
    out_groups.push_back(
        {{"group", key.first},
         {"x", key.second},
         {"finished", finished},
         {"solved", solved},
         {"by_status", g.by_status},
         {"success_rate",
          finished > 0 ? Json(static_cast<double>(solved) / static_cast<double>(finished)) : Json(nullptr)},
         {"metrics", std::move(m)}});
  }
  Json metric_list = Json::array();
  for (const Metric& m : metrics()) metric_list.push_back({{"name", m.name}, {"label", m.label}, {"unit", m.unit}});
  return jsonText(Json{{"family", request.family},
                       {"x", request.x},
                       {"group_by", request.group_by},
                       {"split", request.split},
                       {"include_unsolved", request.include_unsolved},
                       {"metrics", metric_list},
                       {"groups", out_groups}});
}

std::string SeriesQueries::overviewJson() const {
  const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
  const log::SqlRows families = db.select(
      "SELECT r.family, count(*), sum(r.status = 'solved') FROM dash_runs r GROUP BY r.family ORDER BY r.family");
  Json list = Json::array();
  for (const auto& row : families.rows) {
    const std::string family = text(row[0]);
    const log::SqlRows params = db.select(
        "SELECT DISTINCT j.key FROM dash_experiments e, json_each(e.params) j WHERE e.family = ? ORDER BY j.key",
        {family});
    const log::SqlRows configs = db.select(
        "SELECT DISTINCT c.name FROM " + std::string(RunTable::fromClause()) + " WHERE r.family = ? ORDER BY c.name",
        {family});
    Json p = Json::array(), c = Json::array();
    for (const auto& r : params.rows) p.push_back(toJson(r[0]));
    for (const auto& r : configs.rows) c.push_back(toJson(r[0]));
    list.push_back(
        {{"family", family}, {"runs", toJson(row[1])}, {"solved", toJson(row[2])}, {"parameters", p}, {"configs", c}});
  }
  return jsonText(Json{{"families", list}});
}

}  // namespace dash::http
