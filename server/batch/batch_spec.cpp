#include "server/batch/batch_spec.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "engine/core/json_parse.h"
#include "engine/core/json_reader.h"
#include "engine/planners/planner.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "server/batch/progress_printer.h"

namespace dash::batch {

namespace {
// Upper bounds on the spec's numbers: beyond them the runner's time and memory arithmetic (and
// Slurm's minutes and megabytes, as int) would overflow.
constexpr double kMaxTimeLimitSeconds = 7 * 24 * 3600;
constexpr double kMaxMemoryLimitMb = 4 * 1024 * 1024;
constexpr std::size_t kMaxSeeds = 1000000;
constexpr std::int64_t kMaxSeed = std::int64_t{1} << 53;  ///< exact as a JSON number anywhere
}  // namespace

using Json = nlohmann::ordered_json;

const char* toString(SpecErrorKind kind) {
  switch (kind) {
    case SpecErrorKind::kSyntax:
      return "syntax";
    case SpecErrorKind::kUnknownKey:
      return "unknown-key";
    case SpecErrorKind::kMissingKey:
      return "missing-key";
    case SpecErrorKind::kEmptyGrid:
      return "empty-grid";
    case SpecErrorKind::kUnknownFamily:
      return "unknown-family";
    case SpecErrorKind::kOutOfRange:
      return "out-of-range";
    case SpecErrorKind::kBadCombination:
      return "bad-combination";
    case SpecErrorKind::kUnknownPlanner:
      return "unknown-planner";
    case SpecErrorKind::kBadValue:
      return "bad-value";
    case SpecErrorKind::kTooManyRuns:
      return "too-many-runs";
  }
  return "?";
}

namespace {

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

SpecErrorKind specErrorKind(JsonErrorKind kind) {
  switch (kind) {
    case JsonErrorKind::kSyntax:
    case JsonErrorKind::kType: return SpecErrorKind::kSyntax;
    case JsonErrorKind::kMissing: return SpecErrorKind::kMissingKey;
    case JsonErrorKind::kRange: return SpecErrorKind::kOutOfRange;
    case JsonErrorKind::kValue: return SpecErrorKind::kBadValue;
  }
  return SpecErrorKind::kBadValue;
}

/// The shared field reader (engine/core/json_reader.h) with the spec's error kinds and its checks of
/// keys and grids. Messages: "SOURCE: PATH: WHAT".
class Checker : public JsonReader<Json> {
 public:
  explicit Checker(std::string source)
      : JsonReader<Json>([prefix = source.empty() ? std::string() : source + ": "](
                             JsonErrorKind kind, const std::string& where, const std::string& what) {
          throw SpecError(specErrorKind(kind), prefix + (where.empty() ? "" : where + ": ") + what);
        }),
        prefix_(source.empty() ? "" : source + ": ") {}

  using JsonReader<Json>::fail;
  [[noreturn]] void fail(SpecErrorKind kind, const std::string& where, const std::string& what) const {
    throw SpecError(kind, prefix_ + (where.empty() ? "" : where + ": ") + what);
  }

  void keys(const Json& object, const std::string& where, const std::vector<std::string>& allowed,
            const std::vector<std::string>& required) const {
    if (!object.is_object()) fail(SpecErrorKind::kSyntax, where.empty() ? "the spec" : where, "expected an object");
    for (const auto& [key, value] : object.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        fail(SpecErrorKind::kUnknownKey, where.empty() ? key : where + "." + key,
             "unknown key (allowed here: " + joinNames(allowed) + ")");
      }
    }
    for (const auto& key : required) {
      if (!object.contains(key)) {
        fail(SpecErrorKind::kMissingKey, where.empty() ? key : where + "." + key, "required key is missing");
      }
    }
  }

  const Json& nonEmptyArray(const Json& v, const std::string& where) const {
    if (!v.is_array()) fail(SpecErrorKind::kSyntax, where, std::string("expected a list, got ") + v.type_name());
    if (v.empty()) fail(SpecErrorKind::kEmptyGrid, where, "the list is empty: the grid has no runs");
    return v;
  }

 private:
  std::string prefix_;
};

std::string at(const std::string& where, std::size_t i) { return where + "[" + std::to_string(i) + "]"; }

ScenarioEntry parseScenario(const Checker& check, const Json& j, const std::string& where) {
  check.keys(j, where, {"family", "params", "description", "stop_axis"}, {"family"});
  ScenarioEntry entry;
  entry.family = check.string(j["family"], where + ".family");
  const ScenarioFamily* family = findScenarioFamily(entry.family);
  if (family == nullptr) {
    std::vector<std::string> known;
    for (const auto& f : scenarioFamilies()) known.push_back(f.name);
    check.fail(SpecErrorKind::kUnknownFamily, where + ".family",
               "unknown scenario family '" + entry.family + "' (known: " + joinNames(known) + ")");
  }
  const Json params = j.contains("params") ? j["params"] : Json::object();
  const std::string pwhere = where + ".params";
  if (!params.is_object()) check.fail(SpecErrorKind::kSyntax, pwhere, "expected an object");
  for (const auto& [key, value] : params.items()) {
    const bool known =
        std::any_of(family->params.begin(), family->params.end(), [&](const ParamSpec& p) { return p.name == key; });
    if (!known) {
      std::vector<std::string> names;
      for (const auto& p : family->params) names.push_back(p.name + " (" + p.rangeText() + ")");
      check.fail(SpecErrorKind::kUnknownKey, pwhere + "." + key,
                 "unknown parameter of " + entry.family + " (its parameters: " + joinNames(names) + ")");
    }
  }
  for (const ParamSpec& p : family->params) {
    std::vector<int> values;
    if (!params.contains(p.name)) {
      values.push_back(p.default_value);
    } else {
      const Json& v = params[p.name];
      const std::string vwhere = pwhere + "." + p.name;
      std::vector<std::pair<const Json*, std::string>> items;
      if (v.is_array()) {
        check.nonEmptyArray(v, vwhere);
        for (std::size_t i = 0; i < v.size(); ++i) items.emplace_back(&v[i], at(vwhere, i));
      } else {
        items.emplace_back(&v, vwhere);
      }
      for (const auto& [item, iwhere] : items) {
        const std::int64_t x = check.integer(*item, iwhere);
        if (x < p.min || x > p.max) {
          check.fail(SpecErrorKind::kOutOfRange, iwhere,
                     std::to_string(x) + " is out of range " + p.rangeText() + " for " + entry.family + "." + p.name);
        }
        if (p.even_only && x % 2 != 0) {
          check.fail(SpecErrorKind::kOutOfRange, iwhere,
                     std::to_string(x) + " must be even (" + p.rangeText() + ") for " + entry.family + "." + p.name);
        }
        if (std::find(values.begin(), values.end(), static_cast<int>(x)) != values.end()) {
          check.fail(SpecErrorKind::kBadValue, iwhere, std::to_string(x) + " is listed twice");
        }
        values.push_back(static_cast<int>(x));
      }
    }
    entry.params.emplace_back(p.name, std::move(values));
  }
  if (j.contains("stop_axis")) {
    entry.stop_axis = check.string(j["stop_axis"], where + ".stop_axis");
    const bool known = std::any_of(family->params.begin(), family->params.end(),
                                   [&](const ParamSpec& p) { return p.name == entry.stop_axis; });
    if (!known) {
      std::vector<std::string> names;
      for (const auto& p : family->params) names.push_back(p.name);
      check.fail(SpecErrorKind::kBadValue, where + ".stop_axis",
                 "'" + entry.stop_axis + "' is not a parameter of " + entry.family + " (its parameters: " +
                     joinNames(names) + ")");
    }
  }
  return entry;
}

PlannerEntry parsePlanner(const Checker& check, const Json& j, const std::string& where, const SpecOptions& options,
                          std::vector<std::string>& unknown) {
  check.keys(j, where, {"name", "settings", "label"}, {"name"});
  PlannerEntry entry;
  entry.name = check.string(j["name"], where + ".name");
  const std::vector<std::string> names = plannerNames();
  if (std::find(names.begin(), names.end(), entry.name) == names.end()) {
    if (!options.allow_unknown_planners) {
      check.fail(SpecErrorKind::kUnknownPlanner, where + ".name",
                 "unknown planner '" + entry.name + "' (this build has: " + joinNames(names) + ")");
    }
    if (std::find(unknown.begin(), unknown.end(), entry.name) == unknown.end()) unknown.push_back(entry.name);
  }
  Json settings = j.contains("settings") ? j["settings"] : Json::object();
  const std::string swhere = where + ".settings";
  if (!settings.is_object()) check.fail(SpecErrorKind::kSyntax, swhere, "expected an object");
  for (const char* reserved : {"seed", "time_limit"}) {
    if (settings.contains(reserved)) {
      check.fail(SpecErrorKind::kUnknownKey, swhere + "." + reserved,
                 "set by the batch, not per planner (use the spec's 'seeds' and 'time_limit')");
    }
  }
  // Besides these two, a planner's settings are its named parameters (engine/core/planner_params.h).
  std::vector<std::string> allowed{"task_only", "test_fault"};
  if (std::find(names.begin(), names.end(), entry.name) != names.end())
    for (const ParamInfo& p : plannerParameters(entry.name)) allowed.push_back(p.name);
  check.keys(settings, swhere, allowed, {});
  if (std::find(names.begin(), names.end(), entry.name) != names.end()) {
    for (const auto& [key, value] : settings.items()) {
      if (key == "task_only" || key == "test_fault") continue;
      if (!value.is_boolean() && !value.is_number())
        check.fail(SpecErrorKind::kBadValue, swhere + "." + key, "expected true, false or a number");
      try {
        resolveParameters(entry.name, {{key, value.dump()}});
      } catch (const InputError& e) {
        check.fail(SpecErrorKind::kBadValue, swhere + "." + key, e.what());
      }
    }
  }
  if (settings.contains("task_only")) {
    if (!settings["task_only"].is_boolean())
      check.fail(SpecErrorKind::kSyntax, swhere + ".task_only", "expected true or false");
    entry.task_only = settings["task_only"].get<bool>();
  }
  if (settings.contains("test_fault")) {
    entry.test_fault = check.string(settings["test_fault"], swhere + ".test_fault");
    if (entry.test_fault != "abort" && entry.test_fault != "ignore-deadline" && !entry.test_fault.empty()) {
      check.fail(SpecErrorKind::kBadValue, swhere + ".test_fault", "expected \"abort\" or \"ignore-deadline\"");
    }
  }
  // Canonical settings text: keys sorted (std::map-backed json), compact.
  entry.settings_json = nlohmann::json::parse(settings.dump()).dump();
  entry.label = j.contains("label")
                    ? check.string(j["label"], where + ".label")
                    : (entry.settings_json == "{}" ? entry.name : entry.name + " " + entry.settings_json);
  if (entry.label.empty()) check.fail(SpecErrorKind::kBadValue, where + ".label", "must not be empty");
  if (entry.label.find('/') != std::string::npos)
    check.fail(SpecErrorKind::kBadValue, where + ".label", "must not contain '/'");
  return entry;
}

std::vector<std::uint64_t> parseSeeds(const Checker& check, const Json& j) {
  std::vector<std::uint64_t> seeds;
  if (j.is_object()) {
    check.keys(j, "seeds", {"from", "count"}, {"from", "count"});
    const std::int64_t from = check.integer(j["from"], "seeds.from");
    const std::int64_t count = check.integer(j["count"], "seeds.count");
    if (from < 0 || from > kMaxSeed) {
      check.fail(SpecErrorKind::kOutOfRange, "seeds.from", "must be in 0.." + std::to_string(kMaxSeed));
    }
    if (count <= 0) check.fail(SpecErrorKind::kEmptyGrid, "seeds.count", "must be at least 1: the grid has no runs");
    if (count > static_cast<std::int64_t>(kMaxSeeds))
      check.fail(SpecErrorKind::kTooManyRuns, "seeds.count", std::to_string(count) + " seeds");
    for (std::int64_t i = 0; i < count; ++i) seeds.push_back(static_cast<std::uint64_t>(from + i));
    return seeds;
  }
  if (!j.is_array())
    check.fail(SpecErrorKind::kSyntax, "seeds", "expected a list of seeds or {\"from\": S, \"count\": N}");
  check.nonEmptyArray(j, "seeds");
  if (j.size() > kMaxSeeds) check.fail(SpecErrorKind::kTooManyRuns, "seeds", std::to_string(j.size()) + " seeds");
  std::set<std::uint64_t> seen;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::int64_t s = check.integer(j[i], at("seeds", i));
    if (s < 0 || s > kMaxSeed) {
      check.fail(SpecErrorKind::kOutOfRange, at("seeds", i), "must be in 0.." + std::to_string(kMaxSeed));
    }
    if (!seen.insert(static_cast<std::uint64_t>(s)).second) {
      check.fail(SpecErrorKind::kBadValue, at("seeds", i), std::to_string(s) + " is listed twice");
    }
    seeds.push_back(static_cast<std::uint64_t>(s));
  }
  return seeds;
}

/// Every combination of the entry's parameter values, last parameter fastest.
std::vector<std::vector<std::pair<std::string, int>>> combinations(const ScenarioEntry& e) {
  std::vector<std::vector<std::pair<std::string, int>>> out{{}};
  for (const auto& [name, values] : e.params) {
    std::vector<std::vector<std::pair<std::string, int>>> next;
    for (const auto& partial : out) {
      for (int v : values) {
        auto c = partial;
        c.emplace_back(name, v);
        next.push_back(std::move(c));
      }
    }
    out = std::move(next);
  }
  return out;
}

void probeCombinations(const Checker& check, const BatchSpec& spec) {
  std::shared_ptr<const RobotLibrary> library;
  std::set<std::string> done;
  for (std::size_t i = 0; i < spec.scenarios.size(); ++i) {
    const ScenarioEntry& e = spec.scenarios[i];
    for (const auto& combo : combinations(e)) {
      RunSpec probe;
      probe.params = combo;
      if (!done.insert(e.family + " " + probe.paramsText()).second) continue;
      if (!library) library = RobotLibrary::loadDefault();
      try {
        generateScenario(e.family, ScenarioParams(combo), spec.seeds.front(), library,
                         GenerateOptions{.max_attempts = 1, .validate = false});
      } catch (const ScenarioError&) {
        // A layout that failed for this seed: the run will retry with derived seeds. Not a spec error.
      } catch (const InputError& err) {
        check.fail(SpecErrorKind::kBadCombination, at("scenarios", i),
                   e.family + " " + probe.paramsText() + ": " + err.what());
      }
    }
  }
}

}  // namespace

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
    if (key != "task_only" && key != "test_fault") out[key] = value.dump();
  return out;
}

BatchSpec parseBatchSpec(const std::string& json_text, const std::string& source_name, const SpecOptions& options) {
  const Checker check(source_name);
  Json j = parseJsonText(check, json_text);
  check.keys(j, "", {"name", "description", "time_limit", "memory_limit", "scenarios", "planners", "seeds"},
             {"name", "scenarios", "planners", "seeds"});
  BatchSpec spec;
  spec.name = check.string(j["name"], "name");
  if (spec.name.empty()) check.fail(SpecErrorKind::kBadValue, "name", "must not be empty");
  if (j.contains("description")) spec.description = check.string(j["description"], "description");
  if (j.contains("time_limit")) {
    spec.time_limit = check.number(j["time_limit"], "time_limit");
    if (!(spec.time_limit > 0.0) || !(spec.time_limit <= kMaxTimeLimitSeconds)) {
      check.fail(SpecErrorKind::kBadValue, "time_limit",
                 "must be a positive number of seconds, at most " +
                     std::to_string(static_cast<long long>(kMaxTimeLimitSeconds)) + " (a week)");
    }
  }
  if (j.contains("memory_limit")) {
    spec.memory_limit_mb = check.number(j["memory_limit"], "memory_limit");
    if (spec.memory_limit_mb < 0.0 || !(spec.memory_limit_mb <= kMaxMemoryLimitMb) ||
        (spec.memory_limit_mb > 0.0 && spec.memory_limit_mb < 64.0)) {
      check.fail(SpecErrorKind::kBadValue, "memory_limit",
                 "must be 0 (no limit) or from 64 MB to " + std::to_string(static_cast<long long>(kMaxMemoryLimitMb)) +
                     " MB (4 TB)");
    }
  }
  const Json& scenarios = check.nonEmptyArray(j["scenarios"], "scenarios");
  for (std::size_t i = 0; i < scenarios.size(); ++i) {
    spec.scenarios.push_back(parseScenario(check, scenarios[i], at("scenarios", i)));
  }
  const Json& planners = check.nonEmptyArray(j["planners"], "planners");
  std::set<std::string> labels;
  for (std::size_t i = 0; i < planners.size(); ++i) {
    spec.planners.push_back(parsePlanner(check, planners[i], at("planners", i), options, spec.unknown_planners));
    if (!labels.insert(spec.planners.back().label).second) {
      check.fail(SpecErrorKind::kBadValue, at("planners", i),
                 "planner configuration '" + spec.planners.back().label +
                     "' is listed twice (give each a distinct \"label\")");
    }
  }
  spec.seeds = parseSeeds(check, j["seeds"]);

  const std::size_t runs = countRuns(spec);
  if (runs > options.max_runs) {
    check.fail(SpecErrorKind::kTooManyRuns, "",
               "the grid expands to " + std::to_string(runs) + " runs, more than the limit of " +
                   std::to_string(options.max_runs) + " (raise it with --max-runs)");
  }
  // The same scene listed by two scenario entries would be two runs with one key.
  std::set<std::string> keys;
  for (const RunSpec& r : expandRuns(spec)) {
    if (!keys.insert(r.key).second) {
      check.fail(SpecErrorKind::kBadValue, "scenarios",
                 "run " + r.key + " is listed twice (overlapping scenario entries)");
    }
  }
  if (options.check_combinations) probeCombinations(check, spec);
  spec.json = j.dump();
  return spec;
}

BatchSpec loadBatchSpec(const std::string& path, const SpecOptions& options) {
  std::ifstream in(path, std::ios::binary);
  DASH_THROW_UNLESS(in.good(), path + ": cannot read the batch spec");
  std::stringstream text;
  text << in.rdbuf();
  return parseBatchSpec(text.str(), path, options);
}

std::size_t countRuns(const BatchSpec& spec) {
  // Saturating: a hostile grid must not wrap around to a small count and then be expanded.
  constexpr std::size_t kMax = std::numeric_limits<std::size_t>::max();
  auto times = [](std::size_t a, std::size_t b) { return b != 0 && a > kMax / b ? kMax : a * b; };
  std::size_t scenes = 0;
  for (const ScenarioEntry& e : spec.scenarios) {
    std::size_t combos = 1;
    for (const auto& [name, values] : e.params) combos = times(combos, values.size());
    scenes = combos > kMax - scenes ? kMax : scenes + combos;
  }
  return times(times(scenes, spec.seeds.size()), spec.planners.size());
}

std::vector<RunSpec> expandRuns(const BatchSpec& spec) {
  std::vector<RunSpec> runs;
  for (const ScenarioEntry& e : spec.scenarios) {
    for (const auto& combo : combinations(e)) {
      for (std::uint64_t seed : spec.seeds) {
        for (const PlannerEntry& p : spec.planners) {
          RunSpec r;
          r.family = e.family;
          r.params = combo;
          r.seed = seed;
          r.planner = p.name;
          r.label = p.label;
          r.settings_json = p.settings_json;
          r.task_only = p.task_only;
          r.test_fault = p.test_fault;
          r.time_limit = spec.time_limit;
          r.memory_limit_mb = spec.memory_limit_mb;
          r.stop_axis = e.stop_axis;
          std::string params;
          for (const auto& [k, v] : combo) params += (params.empty() ? "" : ",") + k + "=" + std::to_string(v);
          r.key = e.family + "/" + params + "/seed=" + std::to_string(seed) + "/" + p.label;
          r.ordinal = static_cast<int>(runs.size());
          runs.push_back(std::move(r));
        }
      }
    }
  }
  return runs;
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
