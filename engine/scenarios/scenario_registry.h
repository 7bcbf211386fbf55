#pragma once
// Parameterised scenario generators (the paper's Sorting, Wall, Shelf-wall, Stocking and Lab
// families). A generator takes a family, its parameters and a seed and returns a dashbench.scene/1
// scene. Same inputs give byte-identical JSON (sceneToJson) on any machine: every random draw comes
// from a dash::Rng seeded from the inputs through portable mappings (portable_random.h), and no
// unordered container decides an output order.
//
// Every scene returned has passed validateScenario (scenario_validation.h): the checks of
// `dashbench check-scene` plus the handover chain each object needs and the reachability of inspect
// poses. A layout that fails is retried with seeds derived from the given one (Rng::derive); after
// GenerateOptions::max_attempts failures the generator throws ScenarioError. It never returns a
// broken scene.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "engine/scenarios/scenario_params.h"
#include "engine/scenarios/scenario_validation.h"
#include "engine/scene/scene.h"

namespace dash {

/// The parameters asked for cannot give a valid scene (bad combination, or every attempt failed).
class ScenarioError : public InputError {
 public:
  using InputError::InputError;
};

/// One family: its name, one-line summary and parameters (in the order written to the scene).
struct ScenarioFamily {
  std::string name;
  std::string summary;
  std::vector<ParamSpec> params;
};

/// Every family, in the order `dashbench scenario --list` prints them.
const std::vector<ScenarioFamily>& scenarioFamilies();
/// nullptr if there is no such family.
const ScenarioFamily* findScenarioFamily(const std::string& name);
/// The family or an InputError listing the known families.
const ScenarioFamily& scenarioFamily(const std::string& name);

/// Lab: how many lids the sanitisation zone has room for with `containers` containers (fewer than them).
int labZoneLids(int containers);

/// `--list`: each family with its parameters, defaults and ranges (plain text, one block per family).
std::string describeScenarioFamilies();

struct GenerateOptions {
  int max_attempts = 6;  ///< layouts tried (seed, then derived seeds) before giving up
  bool validate = true;  ///< false: skip validateScenario (tests of the raw layout only)
};

/// Generates family `family` with `params` (from resolveParams) and `seed`; robot models come from
/// `library` (kept alive by the scene). Throws InputError for an unknown family or a bad parameter
/// combination, ScenarioError when no valid layout was found.
Scene generateScenario(const std::string& family, const ScenarioParams& params, std::uint64_t seed,
                       std::shared_ptr<const RobotLibrary> library, const GenerateOptions& options = {});

/// A generated scene with what vetted it: the family's validation rules (which grasps its design
/// blocks, where handovers are looked for) and the report (handover graph, per-object transfers).
struct GeneratedScenario {
  Scene scene;
  ValidationSpec validation;
  ScenarioReport report;  ///< empty when options.validate is false
  int attempts = 0;       ///< layouts tried, this one included
};

/// generateScenario, keeping the validation rules and report.
GeneratedScenario generateScenarioDetailed(const std::string& family, const ScenarioParams& params, std::uint64_t seed,
                                           std::shared_ptr<const RobotLibrary> library,
                                           const GenerateOptions& options = {});

/// Convenience: defaults overridden by key=value strings, then generateScenario.
Scene generateScenario(const std::string& family, const std::vector<std::pair<std::string, std::string>>& overrides,
                       std::uint64_t seed, std::shared_ptr<const RobotLibrary> library,
                       const GenerateOptions& options = {});

}  // namespace dash
