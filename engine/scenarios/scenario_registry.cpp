#include "engine/scenarios/scenario_registry.h"

#include <algorithm>
#include <sstream>

#include "engine/scenarios/scenario_families.h"

namespace dash {

namespace {

using Generate = GeneratedLayout (*)(const FamilyInput&);

struct Entry {
  ScenarioFamily family;
  Generate generate;
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> table = {
      {{"sorting",
        "UR5e arms on a ring; cubes go from each arm's cluster to the box of the arm across the ring "
        "(cross sorting) by handovers between neighbours",
        {{.name = "robots", .default_value = 4, .min = 2, .max = 64, .meaning = "arms on the ring"},
         {.name = "objects", .default_value = 8, .min = 1, .max = 256, .meaning = "cubes, dealt round the arms"}}},
       generateSorting},
      {{"wall",
        "the sorting ring with thin tall walls that cut some neighbour handovers; each arc between walls "
        "is mirrored: the arms beside a wall send their cubes to each other the long way round",
        {{.name = "robots", .default_value = 8, .min = 4, .max = 32, .meaning = "arms on the ring"},
         {.name = "objects", .default_value = 8, .min = 1, .max = 128, .meaning = "cubes, dealt round the arms"},
         {.name = "walls",
          .default_value = 1,
          .min = 1,
          .max = 31,
          .meaning = "walls between neighbours: walls-1 fence off pairs, the rest is one long arc; "
                     "beyond robots/2 they split pairs into single arms that sort their own cubes "
                     "(walls <= robots-1)"}}},
       generateWall},
      {{"shelf-wall",
        "arms in rows on both sides of a double-sided shelf whose middle panel is a wall; cubes start on the "
        "far side and fill cubbies rear slot first",
        {{.name = "robots",
          .default_value = 2,
          .min = 2,
          .max = 8,
          .even_only = true,
          .meaning = "arms, half on each side of the shelf"},
         {.name = "objects", .default_value = 8, .min = 2, .max = 32, .meaning = "cubes, two per cubby"}}},
       generateShelfWall},
      {{"stocking",
        "a stocker arm at a shelf and a feeder arm behind it; new items go behind existing ones, which must "
        "be moved out and restocked (non-monotone)",
        {{.name = "layers",
          .default_value = 2,
          .min = 2,
          .max = 3,
          .meaning = "slots per cubby, front to back (existing items + 1 new)"},
         {.name = "objects", .default_value = 8, .min = 4, .max = 28, .meaning = "existing and new items in all"}}},
       generateStocking},
      {{"lab",
        "two gantries over a bench, each able to lift lids and inspect: a container's lid goes to a small "
        "sanitisation zone (room for min(3, containers - 1) lids), the open container is inspected, the lid "
        "goes back",
        {{.name = "containers", .default_value = 4, .min = 2, .max = 24, .meaning = "sealed containers, one lid each"}}},
       generateLab},
  };
  return table;
}

const Entry& entry(const std::string& name) {
  const auto& all = entries();
  const auto it = std::find_if(all.begin(), all.end(), [&](const Entry& e) { return e.family.name == name; });
  if (it == all.end()) {
    std::string known;
    for (const Entry& e : all) known += (known.empty() ? "" : ", ") + e.family.name;
    throw InputError("unknown scenario family '" + name + "' (known: " + known + ")");
  }
  return *it;
}

}  // namespace

const std::vector<ScenarioFamily>& scenarioFamilies() {
  static const std::vector<ScenarioFamily> families = [] {
    std::vector<ScenarioFamily> out;
    for (const Entry& e : entries()) out.push_back(e.family);
    return out;
  }();
  return families;
}

const ScenarioFamily* findScenarioFamily(const std::string& name) {
  for (const ScenarioFamily& f : scenarioFamilies()) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

const ScenarioFamily& scenarioFamily(const std::string& name) { return entry(name).family; }

std::string describeScenarioFamilies() {
  std::ostringstream out;
  for (const ScenarioFamily& f : scenarioFamilies()) {
    out << f.name << ": " << f.summary << "\n";
    for (const ParamSpec& p : f.params) {
      out << "  " << p.name << "=" << p.default_value << "  (" << p.rangeText() << ")  " << p.meaning << "\n";
    }
  }
  return out.str();
}

SceneGenerator generatorRecord(const FamilyInput& in) {
  SceneGenerator g;
  g.name = in.family;
  for (const auto& [key, value] : in.params.values()) g.params.emplace_back(key, static_cast<double>(value));
  g.seed = in.seed;
  return g;
}

std::string sceneName(const FamilyInput& in, const std::string& short_params) {
  return in.family + "-" + short_params + "-s" + std::to_string(in.seed);
}

GeneratedScenario generateScenarioDetailed(const std::string& family, const ScenarioParams& params, std::uint64_t seed,
                                           std::shared_ptr<const RobotLibrary> library,
                                           const GenerateOptions& options) {
  const Entry& e = entry(family);
  DASH_DEMAND(options.max_attempts >= 1);
  std::string last_problem;
  for (int attempt = 0; attempt < options.max_attempts; ++attempt) {
    // The first attempt uses the seed itself; retries use seeds derived from it, so the whole
    // sequence (and the scene it ends with) depends only on the inputs.
    Rng rng(attempt == 0 ? seed : Rng::derive(seed, static_cast<std::uint64_t>(attempt)));
    const FamilyInput in{.family = family, .params = params, .seed = seed, .rng = rng, .library = library};
    GeneratedLayout layout = e.generate(in);
    GeneratedScenario out{.scene = std::move(layout.scene),
                          .validation = std::move(layout.validation),
                          .report = {},
                          .attempts = attempt + 1};
    if (!options.validate) return out;
    out.report = validateScenario(out.scene, out.validation);
    if (out.report.ok()) return out;
    last_problem = out.report.problems.front();
    if (out.report.problems.size() > 1) {
      last_problem += " (and " + std::to_string(out.report.problems.size() - 1) + " more)";
    }
  }
  throw ScenarioError("scenario " + family + " (seed " + std::to_string(seed) + "): no valid layout in " +
                      std::to_string(options.max_attempts) + " attempts; last problem: " + last_problem);
}

Scene generateScenario(const std::string& family, const ScenarioParams& params, std::uint64_t seed,
                       std::shared_ptr<const RobotLibrary> library, const GenerateOptions& options) {
  return std::move(generateScenarioDetailed(family, params, seed, std::move(library), options).scene);
}

Scene generateScenario(const std::string& family, const std::vector<std::pair<std::string, std::string>>& overrides,
                       std::uint64_t seed, std::shared_ptr<const RobotLibrary> library,
                       const GenerateOptions& options) {
  const ScenarioParams params = resolveParams(family, scenarioFamily(family).params, overrides);
  return generateScenario(family, params, seed, std::move(library), options);
}

}  // namespace dash
