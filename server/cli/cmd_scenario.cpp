#include <cerrno>
#include <cstdio>
#include <cstdlib>

#include "engine/core/check.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scenarios/scene_picture.h"
#include "engine/scene/scene_json.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kScenarioHelp;
const char* const kScenarioHelp =
    "usage: dashbench scenario FAMILY [--seed S] [-o FILE | --out FILE] [--png FILE] [key=value ...]\n"
    "       dashbench scenario --list\n"
    "Generate a dashbench.scene/1 scene of a scenario family (sorting, wall, shelf-wall, stocking, lab).\n"
    "The same family, parameters and seed always give the same bytes. Every scene passes check-scene,\n"
    "and every object has a chain of robots with feasible handovers from its start to its goal.\n"
    "  --seed S      random seed, a non-negative integer (default 0)\n"
    "  -o, --out F   write the scene to F (default: standard output)\n"
    "  --png F       also write a top-down picture of the scene to F\n"
    "  --list        print every family with its parameters, defaults and ranges\n"
    "  key=value     a family parameter, e.g. robots=4 objects=8\n"
    "Example: dashbench scenario sorting --seed 3 robots=4 objects=8 -o s.json\n"
    "Exit 0 on success, 2 on an unknown family, parameter or value out of range, or when no valid\n"
    "layout exists for the parameters.\n";

namespace {

std::uint64_t parseSeed(const std::string& text) {
  DASH_THROW_UNLESS(!text.empty() && text.find_first_not_of("0123456789") == std::string::npos,
                    "--seed: '" + text + "' is not a non-negative integer");
  errno = 0;
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  DASH_THROW_UNLESS(errno == 0 && end == text.c_str() + text.size(), "--seed: '" + text + "' is too large");
  return static_cast<std::uint64_t>(v);
}

}  // namespace

int runScenario(const std::vector<std::string>& words) {
  // Args knows long options only: turn the short "-o FILE" / "-oFILE" into "--out".
  std::vector<std::string> normalised;
  for (const std::string& w : words) {
    if (w == "-o") {
      normalised.emplace_back("--out");
    } else if (w.size() > 2 && w.rfind("-o", 0) == 0 && w[2] != '-') {
      normalised.emplace_back("--out=" + w.substr(2));
    } else {
      normalised.push_back(w);
    }
  }
  const Args args(normalised, {.options = {"seed", "out", "png"}, .flags = {"list"}, .key_values = true});
  if (args.has("list")) {
    DASH_THROW_UNLESS(args.positional().empty() && args.keyValues().empty(), "--list takes no other arguments");
    std::fputs(describeScenarioFamilies().c_str(), stdout);
    return kExitOk;
  }
  DASH_THROW_UNLESS(args.positional().size() == 1,
                    args.positional().empty() ? "expected a scenario family (see --list)"
                                              : "expected one scenario family, got '" + args.positional()[1] + "' too");
  const std::string& family = args.positional()[0];
  const ScenarioFamily& spec = scenarioFamily(family);
  const ScenarioParams params = resolveParams(family, spec.params, args.keyValues());
  const std::uint64_t seed = parseSeed(args.get("seed", "0"));
  const Scene scene = generateScenario(family, params, seed, RobotLibrary::loadDefault());
  if (const auto png = args.get("png")) savePng(renderScene(scene), *png);
  if (const auto out = args.get("out")) {
    saveScene(scene, *out);
    std::fprintf(stderr, "dashbench scenario: wrote %s (%zu robots, %zu obstacles, %zu objects)\n", out->c_str(),
                 scene.robots.size(), scene.obstacles.size(), scene.objects.size());
  } else {
    std::fputs(sceneToJson(scene).c_str(), stdout);
  }
  return kExitOk;
}

}  // namespace dash::cli
