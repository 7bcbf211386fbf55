// dashbench validate: checks a plan file against its scene with the project's plan validator.
#include <cmath>
#include <cstdio>

#include "engine/plan/plan_json.h"
#include "engine/plan/plan_validator.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene_json.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

namespace {
constexpr double kMaxValidateClearance = 0.1;  ///< m; more is a typo (mm for m)
}  // namespace

extern const char* const kValidateHelp;
const char* const kValidateHelp =
    "usage: dashbench validate --scene FILE --plan FILE [--clearance M] [--verbose] [--sampled] [--json]\n"
    "                          [--threads N]\n"
    "Check a dashbench.plan/1 file against its dashbench.scene/1 scene: every rule of the contract\n"
    "(trajectories, speeds, events, collisions, goals, tasks). Collisions are certified: between plan\n"
    "points every pair of parts is proved apart (to 0.05 mm of motion) or reported with when and how deep.\n"
    "Prints one line per problem and the smallest clearance over the plan (with --json:\n"
    "{\"valid\", \"samples\", \"problems\": [...], \"closest\"}).\n"
    "  --clearance M  every pair not in contact by design must keep M metres apart (default 0)\n"
    "  --verbose      also print every pair's smallest distance, closest first\n"
    "  --sampled      the older check instead: samples at most 1 cm of motion apart, no certificate\n"
    "Exit status: 0 valid, 1 problems found, 2 bad input (a file that cannot be read or parsed).\n";

int runValidate(const std::vector<std::string>& words) {
  Args args(words, {.options = {"scene", "plan", "threads", "clearance"}, .flags = {"json", "verbose", "sampled"}});
  const std::string scene_path = args.require("scene");
  const std::string plan_path = args.require("plan");
  const Scene scene = loadScene(scene_path, RobotLibrary::loadDefault());
  const Plan plan = loadPlan(plan_path);
  ValidationOptions options;
  options.threads = static_cast<int>(args.integer("threads", 0));
  options.clearance = args.number("clearance", 0.0);
  if (!(options.clearance >= 0.0 && options.clearance <= kMaxValidateClearance)) {
    throw InputError("--clearance must be between 0 and 0.1 (metres)");
  }
  if (args.has("sampled")) options.geometry = ValidationOptions::GeometryCheck::kSampled;
  const ValidationReport report = validatePlan(scene, plan, options);
  if (args.has("json")) {
    std::fputs(validationReportToJson(report).c_str(), stdout);
    return report.valid() ? kExitOk : kExitProblems;
  }
  if (args.has("verbose")) {
    for (const PairClearance& p : report.pairs) {
      std::printf("pair %s - %s: %.4f mm at t=%.6g%s\n", p.a.c_str(), p.b.c_str(), p.distance * 1000.0, p.t,
                  p.contact_allowed ? " (contact allowed)" : "");
    }
  }
  if (options.geometry == ValidationOptions::GeometryCheck::kCertified && options.check_geometry) {
    if (std::isfinite(report.closest.distance)) {
      std::printf("smallest clearance: %.4f mm between %s and %s at t=%.6g (required %.4g mm)\n",
                  report.closest.distance * 1000.0, report.closest.a.c_str(), report.closest.b.c_str(), report.closest.t,
                  options.clearance * 1000.0);
    } else {
      std::printf("smallest clearance: over %.4g mm (no two parts came within 10 mm of the clearance)\n", (options.clearance + 0.01) * 1000.0);
    }
  }
  if (report.valid()) {
    std::printf("valid: %s (%zu %s checked)\n", plan_path.c_str(), report.samples,
                options.geometry == ValidationOptions::GeometryCheck::kCertified ? "pair distances" : "instants");
  } else {
    std::fputs(report.summary().c_str(), stdout);
    std::printf("%zu problem%s in %s\n", report.problems.size(), report.problems.size() == 1 ? "" : "s", plan_path.c_str());
  }
  return report.valid() ? kExitOk : kExitProblems;
}

}  // namespace dash::cli
