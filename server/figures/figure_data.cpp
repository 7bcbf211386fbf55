#include "server/figures/figure_data.h"

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "engine/log/series_name.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash::figures {

namespace {

using Params = std::vector<std::pair<std::string, int>>;

struct Point {
  std::string family;
  Params params;
  std::string planner;
  const log::RunRecord* run = nullptr;  ///< nullptr: skipped
};

Params paramsOf(const std::string& family, const std::string& json) {
  const nlohmann::json j = nlohmann::json::parse(json, nullptr, false);
  Params out;
  if (!j.is_object()) return out;
  if (const ScenarioFamily* f = findScenarioFamily(family)) {
    for (const ParamSpec& p : f->params)
      if (j.contains(p.name) && j[p.name].is_number_integer()) out.emplace_back(p.name, j[p.name].get<int>());
  } else {
    for (const auto& [k, v] : j.items())
      if (v.is_number_integer()) out.emplace_back(k, v.get<int>());
  }
  return out;
}

/// Runs the axis stop rule skipped (none when the batch tables are absent).
std::vector<Point> skippedRuns(const log::ResultsDb& db, const std::string& batch_id) {
  std::vector<Point> out;
  if (batch_id.empty()) return out;
  log::SqlRows rows;
  try {
    rows = db.select(
        "SELECT b.spec FROM dash_batch_skipped s JOIN dash_batch_runs b ON b.batch_id = s.batch_id AND "
        "b.run_key = s.run_key WHERE s.batch_id = ?",
        {batch_id});
  } catch (const std::exception&) {
    return out;  // a database without the batch tables has nothing skipped
  }
  for (const auto& row : rows.rows) {
    const nlohmann::json j = nlohmann::json::parse(std::get<std::string>(row[0]), nullptr, false);
    if (!j.is_object() || !j.contains("family") || !j.contains("params") || !j.contains("label")) continue;
    Point p;
    p.family = j["family"].get<std::string>();
    for (const auto& kv : j["params"]) p.params.emplace_back(kv.at(0).get<std::string>(), kv.at(1).get<int>());
    p.planner = log::seriesName(j["label"].get<std::string>(), j.contains("settings") ? j["settings"].dump() : "{}");
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace

FigureRuns collectFigureRuns(const log::ResultsDb& db, const std::string& batch_id) {
  FigureRuns out;
  log::RunFilter filter;
  filter.batch_id = batch_id;
  filter.limit = std::numeric_limits<std::int32_t>::max();
  filter.newest_first = false;
  for (log::RunRecord& r : db.listRuns(filter))
    if (r.status != log::RunStatus::Running && r.status != log::RunStatus::Cancelled) out.runs.push_back(std::move(r));
  std::vector<Point> points;
  for (const log::RunRecord& r : out.runs)
    points.push_back({r.meta.family, paramsOf(r.meta.family, r.meta.params_json),
                      log::seriesName(r.meta.planner_config_name.empty() ? r.meta.planner : r.meta.planner_config_name,
                                      r.meta.planner_settings_json),
                      &r});
  for (Point& p : skippedRuns(db, batch_id)) points.push_back(std::move(p));

  std::vector<std::string> order;
  for (const auto& f : scenarioFamilies()) order.push_back(f.name);
  for (const Point& p : points)
    if (std::find(order.begin(), order.end(), p.family) == order.end()) order.push_back(p.family);
  for (const std::string& family : order) {
    std::map<std::string, std::set<int>> values;  // parameter -> distinct values
    std::vector<const Point*> mine;
    for (const Point& p : points) {
      if (p.family != family) continue;
      mine.push_back(&p);
      for (const auto& [k, v] : p.params) values[k].insert(v);
    }
    if (mine.empty()) continue;
    FamilyData data;
    data.family = family;
    if (values.count("objects") && values["objects"].size() > 1) {
      data.x_param = "objects";
    } else {
      std::size_t most = 0;
      for (const auto& [k, v] : values)
        if (v.size() > most) {
          most = v.size();
          data.x_param = k;
        }
    }
    std::map<std::pair<std::string, std::string>, Line> lines;
    std::vector<std::pair<std::string, std::string>> line_order;
    std::map<std::string, std::vector<int>> group_values;  // group -> its parameter values, to order by
    for (const Point* p : mine) {
      std::string group;
      std::vector<int> group_key;
      int x = 0;
      for (const auto& [k, v] : p->params) {
        if (k == data.x_param) {
          x = v;
        } else if (values[k].size() > 1) {
          group += (group.empty() ? "" : " ") + k + "=" + std::to_string(v);
          group_key.push_back(v);
        }
      }
      const auto key = std::make_pair(group, p->planner);
      auto [it, inserted] = lines.try_emplace(key);
      if (inserted) {
        it->second.planner = p->planner;
        it->second.group = group;
        line_order.push_back(key);
        group_values.emplace(group, std::move(group_key));
      }
      if (p->run) it->second.runs[x].push_back(p->run);
      else ++it->second.skipped[x];
    }
    // Groups in numeric order (robots=4 before robots=16); within one, planners in the order the batch
    // ran them (the spec's order).
    std::map<std::string, int> planner_rank;
    for (const Point* p : mine) planner_rank.emplace(p->planner, static_cast<int>(planner_rank.size()));
    std::sort(line_order.begin(), line_order.end(), [&](const auto& a, const auto& b) {
      if (a.first != b.first) return group_values[a.first] < group_values[b.first];
      return planner_rank[a.second] < planner_rank[b.second];
    });
    for (const auto& key : line_order) data.lines.push_back(std::move(lines[key]));
    out.families.push_back(std::move(data));
  }
  return out;
}

}  // namespace dash::figures
