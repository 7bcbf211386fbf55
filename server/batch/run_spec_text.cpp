// RunSpec's text forms (its parameters, its JSON for the run-one child and the batch store), and the
// run list with its duration estimate that `dashbench batch plan` prints. Parsing is batch_spec.cpp.
#include <algorithm>
#include <cstdio>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "server/batch/batch_spec.h"
#include "server/batch/progress_printer.h"

namespace dash::batch {

using Json = nlohmann::ordered_json;

std::string RunSpec::paramsJson() const {
  Json j = Json::object();
  for (const auto& [k, v] : params) j[k] = v;
  return j.dump();
}

std::string RunSpec::paramsText() const {
  std::string out;
  for (const auto& [k, v] : params) out += (out.empty() ? "" : " ") + k + "=" + std::to_string(v);
  return out;
}

std::string RunSpec::toJson() const {
  Json j;
  j["key"] = key;
  j["ordinal"] = ordinal;
  j["family"] = family;
  Json p = Json::array();
  for (const auto& [k, v] : params) p.push_back(Json::array({k, v}));
  j["params"] = p;
  j["seed"] = seed;
  j["planner"] = planner;
  j["label"] = label;
  j["settings"] = Json::parse(settings_json);
  j["task_only"] = task_only;
  j["test_fault"] = test_fault;
  j["time_limit"] = time_limit;
  j["memory_limit"] = memory_limit_mb;
  if (!stop_axis.empty()) j["stop_axis"] = stop_axis;
  return j.dump();
}

RunSpec RunSpec::fromJson(const std::string& text) {
  try {
    const Json j = Json::parse(text);
    RunSpec r;
    r.key = j.at("key").get<std::string>();
    r.ordinal = j.at("ordinal").get<int>();
    r.family = j.at("family").get<std::string>();
    for (const auto& p : j.at("params")) r.params.emplace_back(p.at(0).get<std::string>(), p.at(1).get<int>());
    r.seed = j.at("seed").get<std::uint64_t>();
    r.planner = j.at("planner").get<std::string>();
    r.label = j.at("label").get<std::string>();
    r.settings_json = j.at("settings").dump();
    r.task_only = j.at("task_only").get<bool>();
    r.test_fault = j.at("test_fault").get<std::string>();
    r.time_limit = j.at("time_limit").get<double>();
    r.memory_limit_mb = j.at("memory_limit").get<double>();
    if (j.contains("stop_axis")) r.stop_axis = j.at("stop_axis").get<std::string>();
    return r;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("malformed run description: ") + e.what());
  }
}

ParamValues plannerParameterSettings(const std::string& settings_json) {
  ParamValues out;
  const Json settings = Json::parse(settings_json.empty() ? "{}" : settings_json);
  if (!settings.is_object()) return out;
  for (const auto& [key, value] : settings.items())
    if (key != "task_only" && key != "test_fault" && key != "profile") out[key] = value.dump();
  return out;
}

DurationEstimate estimateDuration(const std::vector<RunSpec>& runs, int workers, double setup) {
  DASH_THROW_UNLESS(workers >= 1, "workers must be at least 1");
  DurationEstimate e;
  // Stopped: per stop-axis line only the smallest size runs.
  std::map<std::string, int> smallest;
  auto lineOf = [](const RunSpec& r) {
    std::string line = r.family + "/";
    for (const auto& [k, v] : r.params)
      if (k != r.stop_axis) line += k + "=" + std::to_string(v) + ",";
    return line + "/" + r.label;
  };
  auto axisValue = [](const RunSpec& r) {
    for (const auto& [k, v] : r.params)
      if (k == r.stop_axis) return v;
    return 0;
  };
  for (const RunSpec& r : runs) {
    if (r.stop_axis.empty()) continue;
    const std::string line = lineOf(r);
    const auto it = smallest.find(line);
    if (it == smallest.end() || axisValue(r) < it->second) smallest[line] = axisValue(r);
  }
  for (const RunSpec& r : runs) {
    const double t = r.time_limit + setup;
    e.worst_seconds += t;
    if (r.stop_axis.empty() || axisValue(r) == smallest[lineOf(r)]) e.stopped_seconds += t;
  }
  e.worst_seconds /= workers;
  e.stopped_seconds /= workers;
  return e;
}

namespace {
/// "45s", "2m05s", "1h51m" (the batch progress line's durations; "0.0 h" said nothing for short batches).
std::string duration(double seconds) { return ProgressPrinter::formatDuration(seconds); }
}  // namespace

std::string formatRunList(const BatchSpec& spec, const std::vector<RunSpec>& runs, int workers) {
  std::ostringstream out;
  out << "batch " << spec.name << ": " << runs.size() << (runs.size() == 1 ? " run" : " runs");
  out << " (time limit " << spec.time_limit << " s, memory limit ";
  if (spec.memory_limit_mb > 0) {
    out << spec.memory_limit_mb << " MB)\n";
  } else {
    out << "none)\n";
  }
  const DurationEstimate e = estimateDuration(runs, workers);
  out << "duration with " << workers << " worker" << (workers == 1 ? "" : "s") << ": at most " << duration(e.worst_seconds)
      << " (every run to its time limit)";
  if (e.stopped_seconds < e.worst_seconds)
    out << "; " << duration(e.stopped_seconds) << " when every stop-axis line stops after its smallest size";
  out << "\n";
  if (!spec.description.empty()) out << spec.description << "\n";
  for (const RunSpec& r : runs) out << "  " << r.ordinal + 1 << "  " << r.key << "\n";
  return out.str();
}

}  // namespace dash::batch
