// dashbench validate: checks a plan file against its scene with the project's plan validator.
#include <cstdio>

#include "engine/plan/plan_json.h"
#include "engine/plan/plan_validator.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene_json.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kValidateHelp;
const char* const kValidateHelp =
    "usage: dashbench validate --scene FILE --plan FILE [--json] [--threads N]\n"
    "Check a dashbench.plan/1 file against its dashbench.scene/1 scene: every rule of the contract\n"
    "(trajectories, speeds, events, collisions sampled at 1 cm, goals, tasks).\n"
    "Prints one line per problem (with --json: {\"valid\", \"samples\", \"problems\": [...]}).\n"
    "Exit status: 0 valid, 1 problems found, 2 bad input (a file that cannot be read or parsed).\n";

int runValidate(const std::vector<std::string>& words) {
  Args args(words, {.options = {"scene", "plan", "threads"}, .flags = {"json"}});
  const std::string scene_path = args.require("scene");
  const std::string plan_path = args.require("plan");
  const Scene scene = loadScene(scene_path, RobotLibrary::loadDefault());
  const Plan plan = loadPlan(plan_path);
  ValidationOptions options;
  options.threads = static_cast<int>(args.integer("threads", 0));
  const ValidationReport report = validatePlan(scene, plan, options);
  if (args.has("json")) {
    std::fputs(validationReportToJson(report).c_str(), stdout);
  } else if (report.valid()) {
    std::printf("valid: %s (%zu instants checked)\n", plan_path.c_str(), report.samples);
  } else {
    std::fputs(report.summary().c_str(), stdout);
    std::printf("%zu problem%s in %s\n", report.problems.size(), report.problems.size() == 1 ? "" : "s", plan_path.c_str());
  }
  return report.valid() ? kExitOk : kExitProblems;
}

}  // namespace dash::cli
