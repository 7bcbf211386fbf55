#pragma once
// Batch spec files (experiments/*.json): a grid of scenario families x parameter values x planner
// configurations x seeds, with a per-run time and memory limit. Parsing validates strictly and
// throws SpecError, whose kind() says which rule was broken and whose message names the file and
// the offending field ("sorting.json: scenarios[0].params.robots[2]: 40 is out of range 2..32").
//
// Hostile specs are bounded before anything is expanded (issue 40): names at most 128 bytes, labels
// 256, the description 4096; the run count from the grid's sizes and the seed count; and the bytes
// the runs would take once expanded (32 MB).
//
// Format (every key but description, time_limit and memory_limit is required):
//   {
//     "name": "sorting",
//     "description": "Lazy-DaSH vs DaSH on sorting",
//     "time_limit": 300,          // seconds per run (the planner's deadline, enforced from outside too)
//     "memory_limit": 8192,       // MB per run (RLIMIT_AS of the run's process); 0: none
//     "scenarios": [ {"family": "sorting", "params": {"robots": [4, 8], "objects": [8, 16]},
//                     "stop_axis": "objects"} ],   // optional: see axis_stop.h
//     "planners": [ {"name": "lazy-dash", "settings": {"task_only": false}, "label": "lazy-dash"} ],
//     "seeds": {"from": 1, "count": 5}      // or a list: [1, 2, 3]
//   }
// A parameter value is an integer or a list of integers; parameters left out take the family's
// default. Planner settings: "task_only" (bool), "test_fault" (string, tests only).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/check.h"
#include "engine/core/planner_params.h"

namespace dash::batch {

enum class SpecErrorKind {
  kSyntax,          ///< not JSON, or a value of the wrong type
  kUnknownKey,      ///< a key the format does not have
  kMissingKey,      ///< a required key is absent
  kEmptyGrid,       ///< an empty list of scenarios, planners, seeds or parameter values
  kUnknownFamily,   ///< a scenario family the registry does not know
  kOutOfRange,      ///< a parameter value outside the registry's range (or odd where even is needed)
  kBadCombination,  ///< parameter values the family's generator refuses together (walls >= robots)
  kUnknownPlanner,  ///< a planner name not in plannerNames()
  kBadValue,        ///< a limit that is not positive, a duplicate planner label, a duplicate run
  kTooManyRuns,     ///< the grid expands to more runs than allowed
};
const char* toString(SpecErrorKind kind);

class SpecError : public InputError {
 public:
  SpecError(SpecErrorKind kind, const std::string& message) : InputError(message), kind_(kind) {}
  SpecErrorKind kind() const { return kind_; }

 private:
  SpecErrorKind kind_;
};

struct SpecOptions {
  std::size_t max_runs = 10000;
  /// How the refusal of a spec over max_runs says to raise the limit (the option of the program).
  const char* max_runs_advice = "raise it with --max-runs";
  /// Collect unknown planner names into BatchSpec::unknown_planners instead of throwing (so a test
  /// can validate a spec that names a planner this build does not have yet, and skip running it).
  bool allow_unknown_planners = false;
  /// Probe each parameter combination with the family's generator (one layout, no validation) so
  /// that combinations it refuses (e.g. walls >= robots) are reported before the batch starts.
  bool check_combinations = true;
};

struct PlannerEntry {
  std::string name;           ///< "lazy-dash", "dash"
  std::string label;          ///< unique within the spec; the run's planner configuration name
  std::string settings_json;  ///< canonical JSON object of the settings given: {"task_only":true}
  bool task_only = false;
  std::string test_fault;
};

struct ScenarioEntry {
  std::string family;
  /// Every parameter of the family, in the family's order, with the values to sweep.
  std::vector<std::pair<std::string, std::vector<int>>> params;
  /// A parameter along which a planner that fails a size on every seed skips the larger sizes
  /// (axis_stop.h); empty: none.
  std::string stop_axis;
};

struct BatchSpec {
  std::string name;
  std::string description;
  double time_limit = 60.0;       ///< seconds per run
  double memory_limit_mb = 4096;  ///< per run; 0: no limit
  std::vector<ScenarioEntry> scenarios;
  std::vector<PlannerEntry> planners;
  std::vector<std::uint64_t> seeds;
  std::string json;                           ///< the spec as parsed (compact JSON), stored with the batch
  std::vector<std::string> unknown_planners;  ///< only with SpecOptions::allow_unknown_planners
};

/// One run of a batch. Its key is stable (derived from the content, not the position) and unique
/// within the batch: "sorting/robots=4,objects=8/seed=1/lazy-dash".
struct RunSpec {
  std::string key;
  int ordinal = 0;  ///< position in the expanded list (the order runs start in)
  std::string family;
  std::vector<std::pair<std::string, int>> params;  ///< family order
  std::uint64_t seed = 0;
  std::string planner;
  std::string label;
  std::string settings_json = "{}";
  bool task_only = false;
  std::string test_fault;
  double time_limit = 60.0;
  double memory_limit_mb = 0.0;
  std::string stop_axis;  ///< the scenario entry's stop_axis (axis_stop.h); empty: none

  /// {"robots":4,"objects":8}: the run's scenario parameters as a flat JSON object.
  std::string paramsJson() const;
  /// "robots=4 objects=8".
  std::string paramsText() const;
  /// The whole run as one JSON object (what the run-one child receives); fromJson reverses it.
  std::string toJson() const;
  static RunSpec fromJson(const std::string& text);
};

/// The named planner parameters among a run's settings (every key but task_only and test_fault), as
/// text for resolveParameters.
ParamValues plannerParameterSettings(const std::string& settings_json);

/// Parses and validates a spec. `source_name` prefixes messages (a file name, or empty).
BatchSpec parseBatchSpec(const std::string& json_text, const std::string& source_name = "",
                         const SpecOptions& options = {});
/// Reads `path` and parses it; InputError if it cannot be read.
BatchSpec loadBatchSpec(const std::string& path, const SpecOptions& options = {});

/// The runs of the grid: for each scenario entry, each parameter combination (last parameter
/// fastest), each seed, each planner (so that planners compared on one scene run side by side).
/// At most `limit` of them: the first ones (a preview need not expand the whole grid).
std::vector<RunSpec> expandRuns(const BatchSpec& spec, std::size_t limit = static_cast<std::size_t>(-1));
/// The number of runs expandRuns would return, from the grid's sizes (saturating, nothing expanded).
std::size_t countRuns(const BatchSpec& spec);

/// `dashbench batch plan`: a header (name, limits, run count, duration estimate) and one line per run.
std::string formatRunList(const BatchSpec& spec, const std::vector<RunSpec>& runs, int workers = 1);

/// How long a batch may take with `workers` runs at once: `worst` has every run reach its time limit
/// (plus `setup` seconds each to generate its scene); `stopped` is the same bound when every stop
/// axis line fails at its smallest size (what the axis stop rule can save at most).
struct DurationEstimate {
  double worst_seconds = 0.0;
  double stopped_seconds = 0.0;
};
DurationEstimate estimateDuration(const std::vector<RunSpec>& runs, int workers, double setup = 5.0);

}  // namespace dash::batch
