#include <atomic>
#include <csignal>
#include <cstdio>
#include <fstream>

#include "engine/collision/collision_world.h"
#include "engine/collision/scene_check.h"
#include "engine/core/check.h"
#include "engine/core/planner_params.h"
#include "engine/log/results_db.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/planner.h"
#include "engine/planners/progress_sink.h"
#include "engine/scene/scene_json.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

namespace {

/// The run's figures after the status line, for people comparing runs from a terminal.
void printRunSummary(const PlanStats& stats) {
  std::fprintf(stderr, "time:");
  for (int p = 0; p < log::kPhaseCount; ++p) {
    if (stats.phase_seconds[p] <= 0.0) continue;
    std::fprintf(stderr, "  %s %.2f s", log::toString(static_cast<log::Phase>(p)), stats.phase_seconds[p]);
  }
  std::fprintf(stderr, "  total %.2f s (wall %.2f s)\n", log::phaseSum(stats.phase_seconds), stats.wall_seconds);
  const RepresentationCounts& n = stats.sizes;
  std::fprintf(stderr, "sizes: H_T %zu/%zu  H_TE %zu/%zu  H_M %zu/%zu  H_ME %zu/%zu  roadmaps %lld/%lld\n",
               n.task_vertices, n.task_hyperarcs, n.task_extended_vertices, n.task_extended_hyperarcs,
               n.motion_vertices, n.motion_hyperarcs, n.motion_extended_vertices, n.motion_extended_hyperarcs,
               static_cast<long long>(stats.roadmap_vertices), static_cast<long long>(stats.roadmap_edges));
  if (!stats.roadmaps.empty()) {
    std::fprintf(stderr, "roadmaps per planning space:");
    for (const RoadmapSize& r : stats.roadmaps)
      std::fprintf(stderr, "  %s %lld/%lld", r.space.c_str(), static_cast<long long>(r.vertices),
                   static_cast<long long>(r.edges));
    std::fprintf(stderr, "\n");
  }
  std::fprintf(stderr, "collision checks: %lld eager, %lld lazy  constraints: %lld task, %lld motion  expansions: %lld\n",
               static_cast<long long>(stats.collision_checks_eager), static_cast<long long>(stats.collision_checks_lazy),
               static_cast<long long>(stats.task_constraints), static_cast<long long>(stats.motion_constraints),
               static_cast<long long>(stats.task_space_expansions));
  std::fprintf(stderr, "peak memory: %.1f MB\n", log::processPeakMemoryMb());
}

}  // namespace

extern const char* const kPlanHelp;
const char* const kPlanHelp =
    "usage: dashbench plan --scene FILE [--planner lazy-dash|dash] [--seed S] [--time-limit SEC]\n"
    "                      [--clearance M] [--threads N]\n"
    "                      [--out PLAN.json] [--task-only] [--json] [--quiet]\n"
    "                      [--set NAME=VALUE]... [--profile paper|default] [--params] [--progress-every SEC]\n"
    "                      [--no-scene-check]\n"
    "Plan for a scene. The scene is checked first (as `dashbench check-scene` does): a robot that\n"
    "collides at home, an object that does not rest on a surface or that no robot can grasp is named\n"
    "and nothing is planned (exit 2). Progress (phase, iteration, representation sizes, elapsed time; in conflict\n"
    "resolution the steps scheduled of the plan's, the step's robots and steps per second) goes to\n"
    "stderr, a line at least every second; the summary at the end ends with the peak memory.\n"
    "Ctrl-C stops the planner cleanly.\n"
    "  --planner NAME   lazy-dash (default) or dash (the DaSH baseline: exhaustive, validated)\n"
    "  --seed S         the run's seed (roadmaps, samplers); default 1\n"
    "  --time-limit SEC default 600\n"
    "  --clearance M    metres every check keeps between parts not in contact by design (default 0.002)\n"
    "  --threads N      threads of the plan validator the planner runs on each schedule (0: the\n"
    "                   hardware's, default) and of conflict resolution's checks (0: the hardware's,\n"
    "                   up to 2; 8 at most); the plan is the same for any number\n"
    "  --out FILE       write the dashbench.plan/1 file when solved\n"
    "  --task-only      stop after the task layer and print the unvalidated schedule\n"
    "  --json           with --task-only: print the schedule as JSON\n"
    "  --verbose        also print every constraint and task space expansion as it is learned\n"
    "  --progress-every SEC  at most one progress line per SEC while events come (default 0.5;\n"
    "                   0: one per event); a quiet second still gets one\n"
    "  --set NAME=VALUE set a named planner parameter (repeatable; see --params)\n"
    "  --profile NAME   paper: every extension beyond the published algorithm off; default: none\n"
    "                   (--set applies after the profile)\n"
    "  --params         list the planner parameters (both planners without --planner) and exit\n"
    "  --markdown       with --params: as the Markdown table of docs/planners.md\n"
    "  --no-scene-check plan without checking the scene first (the planner then reports what it finds)\n"
    "Exit codes: 0 solved, 3 not solved in time or infeasible, 2 bad input (a scene with problems too).\n";

namespace {
std::atomic<bool> g_stop{false};

/// check-scene's problems of `scene` on stderr; true if there are any. A scene the planner cannot
/// solve for a reason the check names (an object below the table) would otherwise end "infeasible"
/// after the whole search, without the reason.
bool reportSceneProblems(const Scene& scene, const std::string& path) {
  const std::vector<std::string> problems = findSceneProblems(scene);
  for (const std::string& problem : problems) std::fprintf(stderr, "%s: %s\n", path.c_str(), problem.c_str());
  if (problems.empty()) return false;
  std::fprintf(stderr, "dashbench plan: the scene has %zu problem%s (as `dashbench check-scene` reports): nothing planned\n",
               problems.size(), problems.size() == 1 ? "" : "s");
  return true;
}

// g_stop is set by SIGINT/SIGTERM: the deadline's stop flag.
void onPlanInterrupt(int) { g_stop.store(true); }
}  // namespace

int runPlan(const std::vector<std::string>& words) {
  Args args(words, {.options = {"scene", "planner", "seed", "time-limit", "out", "test-fault", "profile", "clearance",
                                "threads", "progress-every"},
                    .flags = {"task-only", "json", "quiet", "verbose", "params", "markdown", "no-scene-check"},
                    .repeated = {"set"}});
  if (args.has("params")) {
    const auto planner = args.get("planner");
    if (planner) plannerParameters(*planner);  // an unknown name is bad input
    for (const std::string& name : plannerNames())
      if (!planner || *planner == name)
        std::printf("%s\n", (args.has("markdown") ? parametersMarkdown(name) : describeParameters(name)).c_str());
    return kExitOk;
  }
  const std::string planner_name = args.get("planner", "lazy-dash");
  ParamValues params = profileOverrides(planner_name, args.get("profile", "default"));
  for (const std::string& assignment : args.all("set")) {
    auto [name, value] = parseAssignment(assignment);
    params[name] = value;
  }
  if (const auto clearance = args.get("clearance")) params["clearance"] = *clearance;  // = --set clearance=M
  if (const auto threads = args.get("threads")) params["validation_threads"] = *threads;  // = --set validation_threads=N
  resolveParameters(planner_name, params);  // every name and value checked before the scene is read
  const double progress_every = args.number("progress-every", 0.5);
  DASH_THROW_UNLESS(progress_every >= 0.0, "--progress-every must be 0 or more");
  const std::string scene_path = args.require("scene");
  const Scene scene = loadScene(scene_path, RobotLibrary::loadDefault());
  if (!args.has("no-scene-check") && reportSceneProblems(scene, scene_path)) return kExitBadInput;
  PlannerSettings settings;
  settings.seed = static_cast<std::uint64_t>(args.integer("seed", 1));
  settings.time_limit = args.number("time-limit", 600.0);
  DASH_THROW_UNLESS(settings.time_limit > 0.0, "--time-limit must be positive");
  settings.task_only = args.has("task-only");
  settings.test_fault = args.get("test-fault", "");
  settings.params = params;
  auto planner = makePlanner(planner_name);

  std::signal(SIGINT, onPlanInterrupt);
  std::signal(SIGTERM, onPlanInterrupt);
  ProgressSink progress(stderr, args.has("verbose"), progress_every);
  // A line at least every second even while one step takes long (it prints, never steers the planner).
  if (!args.has("quiet")) progress.startTicker(1.0);
  const Deadline deadline(settings.time_limit, &g_stop);
  const PlanResult result = planner->solve(scene, settings, deadline, args.has("quiet") ? nullptr : &progress);
  progress.stopTicker();
  if (!args.has("quiet")) {
    progress.flush();
    printRunSummary(result.stats);
  }

  if (result.outcome != PlanOutcome::kSolved) {
    std::fprintf(stderr, "dashbench plan: %s: %s\n", toString(result.outcome), result.message.c_str());
    std::printf("status: %s\n", toString(result.outcome));
    return kExitNotSolved;
  }
  if (settings.task_only) {
    if (args.has("json")) {
      std::printf("%s\n", result.task_plan_json.c_str());
    } else {
      std::printf("unvalidated schedule (%s, task-level feasible):\n%s", scene.name.c_str(), result.message.c_str());
    }
    return kExitOk;
  }
  if (auto out = args.get("out")) savePlan(*result.plan, *out);
  std::printf("status: solved  makespan %.2f s\n", result.plan->makespan);
  return kExitOk;
}

}  // namespace dash::cli
