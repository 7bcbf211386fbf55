// One Lazy-DaSH run with the collision queries' fast path (engine/collision/cover_check.h) off, then
// on, on the same scene and seed, each in a child forked from one state (OMPL's process-wide generator,
// as tests/collision/cover_plan_test.cpp): the planner's seconds per phase, the child's CPU seconds,
// and whether the two plans are byte for byte the same (issue 38: they must be).
//
//   build/cover_plans FAMILY [K=V ...] [--seed N] [--time-limit SEC]
//   e.g. build/cover_plans sorting robots=16 objects=64 --seed 1 --time-limit 600
// Exit: 0 same plan (or the same failure) both ways, 1 the runs differ, 2 bad arguments.
#include <ompl/util/RandomNumbers.h>

#include <cstdio>
#include <string>
#include <vector>

#include "engine/collision/cover_check.h"
#include "engine/core/forked_run.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash {
namespace {

struct Run {
  std::string summary;  ///< outcome and seconds per phase, one line
  std::string plan;     ///< the plan's JSON (empty if none)
  double cpu_seconds = 0.0;
};

std::string solveToText(const Scene& scene, std::uint64_t seed, double time_limit) {
  PlannerSettings settings;
  settings.seed = seed;
  settings.time_limit = time_limit;
  const PlanResult r = makePlanner("lazy-dash")->solve(scene, settings, Deadline(time_limit), nullptr);
  const char* names[log::kPhaseCount] = {"task_construction",   "task_query",   "task_conflict_detection",
                                    "motion_construction", "motion_query", "conflict_resolution",
                                    "validation",          "other"};
  std::string line = std::string(toString(r.outcome)) + ", wall " + std::to_string(r.stats.wall_seconds) + " s:";
  for (int p = 0; p < log::kPhaseCount; ++p)
    line += std::string(" ") + names[p] + " " + std::to_string(r.stats.phase_seconds[static_cast<std::size_t>(p)]);
  return line + "\n" + (r.plan ? planToJson(*r.plan) : std::string());
}

Run runInChild(const Scene& scene, bool fast_path, std::uint64_t seed, double time_limit) {
  const ForkedRun forked = runForked([&] {
    setCoverFastPath(fast_path);
    return solveToText(scene, seed, time_limit);
  });
  Run run;
  const std::size_t eol = forked.output.find('\n');
  run.summary = forked.finished ? forked.output.substr(0, eol) : "the child run did not finish";
  run.plan = eol == std::string::npos ? std::string() : forked.output.substr(eol + 1);
  run.cpu_seconds = forked.cpu_seconds;
  return run;
}

}  // namespace
}  // namespace dash

int main(int argc, char** argv) {
  using namespace dash;
  if (argc < 2) {
    std::fprintf(stderr, "usage: cover_plans FAMILY [K=V ...] [--seed N] [--time-limit SEC]\n");
    return 2;
  }
  std::vector<std::pair<std::string, std::string>> params;
  std::uint64_t seed = 1;
  double time_limit = 600.0;
  try {
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--seed" && i + 1 < argc) {
        seed = std::stoull(argv[++i]);
      } else if (a == "--time-limit" && i + 1 < argc) {
        time_limit = std::stod(argv[++i]);
      } else if (const auto eq = a.find('='); eq != std::string::npos) {
        params.emplace_back(a.substr(0, eq), a.substr(eq + 1));
      } else {
        std::fprintf(stderr, "cover_plans: unknown argument '%s'\n", a.c_str());
        return 2;
      }
    }
    const Scene scene = generateScenario(argv[1], params, seed, RobotLibrary::loadDefault());
    const ompl::RNG started;  // both children inherit this state of OMPL's generator
    const Run off = runInChild(scene, false, seed, time_limit);
    const Run on = runInChild(scene, true, seed, time_limit);
    std::printf("fast path off: cpu %.2f s; %s\n", off.cpu_seconds, off.summary.c_str());
    std::printf("fast path on:  cpu %.2f s; %s\n", on.cpu_seconds, on.summary.c_str());
    const bool same = off.plan == on.plan &&
                      off.summary.substr(0, off.summary.find(',')) == on.summary.substr(0, on.summary.find(','));
    std::printf("cpu ratio off/on: %.2f; plans %s\n", on.cpu_seconds > 0 ? off.cpu_seconds / on.cpu_seconds : 0.0,
                same ? "identical" : "DIFFER");
    return same ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "cover_plans: %s\n", e.what());
    return 2;
  }
}
