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
// Text that every run repeats (its key, its label, its stored description): a 30 KB label times 5000
// runs took the server from 217 to 649 MB (issue 40). Names and labels are names, not documents.
constexpr std::size_t kMaxNameBytes = 128;
constexpr std::size_t kMaxLabelBytes = 256;
constexpr std::size_t kMaxDescriptionBytes = 4096;  ///< stored once, with the spec
/// What a spec's runs may take in all (their keys, labels and descriptions as the runner stores
/// them), counted from the grid's sizes before anything is expanded.
constexpr std::size_t kMaxExpandedBytes = std::size_t{32} << 20;
constexpr std::size_t kSaturated = std::numeric_limits<std::size_t>::max();

std::size_t times(std::size_t a, std::size_t b) { return b != 0 && a > kSaturated / b ? kSaturated : a * b; }
std::size_t plus(std::size_t a, std::size_t b) { return a > kSaturated - b ? kSaturated : a + b; }
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

void checkLength(const Checker& check, const std::string& text, const std::string& where, std::size_t max) {
  if (text.size() > max) {
    check.fail(SpecErrorKind::kBadValue, where,
               "is " + std::to_string(text.size()) + " bytes long, more than the limit of " + std::to_string(max));
  }
}

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

/// A planner entry's "profile" (engine/core/planner_params.h: "paper" or "default"): its parameter
/// values go into the settings under those given explicitly (which win, as --set after --profile),
/// and the settings record it as "profile", so every run's results row says which profile it ran.
void applyProfile(const Checker& check, const Json& value, const std::string& where, const std::string& planner,
                  Json& settings) {
  const std::string profile = check.string(value, where);
  const std::vector<std::string> names = plannerNames();
  const bool known = std::find(names.begin(), names.end(), planner) != names.end();
  ParamValues overrides;
  try {
    // A planner of another build (allow_unknown_planners): the profile is recorded, its build applies it.
    overrides = profileOverrides(known ? planner : names.front(), profile);
    if (!known) overrides.clear();
  } catch (const InputError& e) {
    check.fail(SpecErrorKind::kBadValue, where, e.what());
  }
  for (const auto& [name, text] : overrides)
    if (!settings.contains(name)) settings[name] = Json::parse(text);  // canonical true/false/numbers
  settings["profile"] = profile;
}

PlannerEntry parsePlanner(const Checker& check, const Json& j, const std::string& where, const SpecOptions& options,
                          std::vector<std::string>& unknown) {
  check.keys(j, where, {"name", "profile", "settings", "label"}, {"name"});
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
  const std::string given = nlohmann::json::parse(settings.dump()).dump();
  if (j.contains("profile")) applyProfile(check, j["profile"], where + ".profile", entry.name, settings);
  entry.settings_json = nlohmann::json::parse(settings.dump()).dump();
  // Unlabelled: the planner, its profile ("dash (paper)", not the profile's expanded parameters), and
  // the settings given.
  std::string label = entry.name;
  if (j.contains("profile") && j["profile"].is_string()) label += " (" + j["profile"].get<std::string>() + ")";
  if (given != "{}") label += " " + given;
  entry.label = j.contains("label") ? check.string(j["label"], where + ".label") : label;
  if (entry.label.empty()) check.fail(SpecErrorKind::kBadValue, where + ".label", "must not be empty");
  if (entry.label.size() > kMaxLabelBytes) {
    check.fail(SpecErrorKind::kBadValue, where + ".label",
               (j.contains("label") ? "is " : "made from the settings is ") + std::to_string(entry.label.size()) +
                   " bytes long, more than the limit of " + std::to_string(kMaxLabelBytes) +
                   (j.contains("label") ? "" : ": give the configuration a shorter \"label\""));
  }
  if (entry.label.find('/') != std::string::npos)
    check.fail(SpecErrorKind::kBadValue, where + ".label", "must not contain '/'");
  return entry;
}

[[noreturn]] void refuseTooManyRuns(const Checker& check, std::size_t runs, const SpecOptions& options) {
  check.fail(SpecErrorKind::kTooManyRuns, "",
             "the grid expands to " + (runs == kSaturated ? std::string("more than 2^64") : std::to_string(runs)) +
                 " runs, more than the limit of " + std::to_string(options.max_runs) + " (" + options.max_runs_advice +
                 ")");
}

/// The seeds; `runs_per_seed` (scenes x planners) refuses a grid of too many runs from the seed
/// count alone, before the list is built.
std::vector<std::uint64_t> parseSeeds(const Checker& check, const Json& j, std::size_t runs_per_seed,
                                      const SpecOptions& options) {
  const auto refuseCount = [&](std::size_t count) {
    if (times(count, runs_per_seed) > options.max_runs) refuseTooManyRuns(check, times(count, runs_per_seed), options);
  };
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
    refuseCount(static_cast<std::size_t>(count));
    for (std::int64_t i = 0; i < count; ++i) seeds.push_back(static_cast<std::uint64_t>(from + i));
    return seeds;
  }
  if (!j.is_array())
    check.fail(SpecErrorKind::kSyntax, "seeds", "expected a list of seeds or {\"from\": S, \"count\": N}");
  check.nonEmptyArray(j, "seeds");
  if (j.size() > kMaxSeeds) check.fail(SpecErrorKind::kTooManyRuns, "seeds", std::to_string(j.size()) + " seeds");
  refuseCount(j.size());
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

/// Scenes of the grid: parameter combinations summed over the scenario entries (saturating).
std::size_t sceneCount(const BatchSpec& spec) {
  std::size_t scenes = 0;
  for (const ScenarioEntry& e : spec.scenarios) {
    std::size_t combos = 1;
    for (const auto& [name, values] : e.params) combos = times(combos, values.size());
    scenes = plus(scenes, combos);
  }
  return scenes;
}

/// The same scene listed by two scenario entries would be runs with one key. Called once the run
/// count is within the limit (scenes <= runs).
void checkScenesOnce(const Checker& check, const BatchSpec& spec) {
  std::set<std::string> scenes;
  for (const ScenarioEntry& e : spec.scenarios) {
    for (const auto& combo : combinations(e)) {
      RunSpec probe;
      probe.params = combo;
      if (!scenes.insert(e.family + " " + probe.paramsText()).second) {
        check.fail(
            SpecErrorKind::kBadValue, "scenarios",
            "the scene " + e.family + " " + probe.paramsText() + " is listed twice (overlapping scenario entries)");
      }
    }
  }
}

/// About what the runs of the grid take once expanded and stored (each run's key, label, settings
/// and description, as RunSpec and as its stored JSON), from the grid's sizes: nothing is expanded.
std::size_t expandedBytes(const BatchSpec& spec) {
  constexpr std::size_t kPerRun = 512;  // the RunSpec, its fixed JSON keys, numbers, the index entry
  std::size_t per_seed = 0;
  for (const ScenarioEntry& e : spec.scenarios) {
    std::size_t combos = 1;
    std::size_t params_text = 0;
    for (const auto& [name, values] : e.params) {
      combos = times(combos, values.size());
      params_text += name.size() + 16;  // "name=NUMBER," and ["name", NUMBER]
    }
    std::size_t planners = 0;
    for (const PlannerEntry& p : spec.planners) {
      const std::size_t key = e.family.size() + params_text + 32 + p.label.size();
      planners = plus(planners, kPerRun + 3 * key + 2 * (p.label.size() + p.settings_json.size()) + e.stop_axis.size() +
                                    p.name.size() + p.test_fault.size());
    }
    per_seed = plus(per_seed, times(combos, planners));
  }
  return times(per_seed, spec.seeds.size());
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

BatchSpec parseBatchSpec(const std::string& json_text, const std::string& source_name, const SpecOptions& options) {
  const Checker check(source_name);
  Json j = parseJsonText(check, json_text);
  check.keys(j, "", {"name", "description", "time_limit", "memory_limit", "scenarios", "planners", "seeds"},
             {"name", "scenarios", "planners", "seeds"});
  BatchSpec spec;
  spec.name = check.string(j["name"], "name");
  if (spec.name.empty()) check.fail(SpecErrorKind::kBadValue, "name", "must not be empty");
  checkLength(check, spec.name, "name", kMaxNameBytes);
  if (j.contains("description")) spec.description = check.string(j["description"], "description");
  checkLength(check, spec.description, "description", kMaxDescriptionBytes);
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
  spec.seeds = parseSeeds(check, j["seeds"], times(sceneCount(spec), spec.planners.size()), options);
  const std::size_t runs = countRuns(spec);
  if (runs > options.max_runs) refuseTooManyRuns(check, runs, options);
  checkScenesOnce(check, spec);
  const std::size_t bytes = expandedBytes(spec);
  if (bytes > kMaxExpandedBytes) {
    check.fail(SpecErrorKind::kTooManyRuns, "",
               "the grid's " + std::to_string(runs) + " runs would take about " + std::to_string(bytes >> 20) +
                   " MB to describe, more than the limit of " + std::to_string(kMaxExpandedBytes >> 20) +
                   " MB (fewer runs, or shorter labels)");
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
  return times(times(sceneCount(spec), spec.seeds.size()), spec.planners.size());
}

std::vector<RunSpec> expandRuns(const BatchSpec& spec, std::size_t limit) {
  std::vector<RunSpec> runs;
  runs.reserve(std::min(limit, countRuns(spec)));
  for (const ScenarioEntry& e : spec.scenarios) {
    for (const auto& combo : combinations(e)) {
      std::string params;
      for (const auto& [k, v] : combo) params += (params.empty() ? "" : ",") + k + "=" + std::to_string(v);
      for (std::uint64_t seed : spec.seeds) {
        for (const PlannerEntry& p : spec.planners) {
          if (runs.size() >= limit) return runs;
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
          r.key = e.family + "/" + params + "/seed=" + std::to_string(seed) + "/" + p.label;
          r.ordinal = static_cast<int>(runs.size());
          runs.push_back(std::move(r));
        }
      }
    }
  }
  return runs;
}

}  // namespace dash::batch
