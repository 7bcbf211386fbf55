// dashbench tpg: the temporal plan graph of a plan (engine/tpg/tpg.h), and the replay check that
// executions respecting it pass the certified validator (engine/tpg/tpg_replay.h).
#include <chrono>
#include <cstdio>
#include <map>

#include "engine/core/check.h"
#include "engine/plan/plan_json.h"
#include "engine/plan/plan_validator.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene_json.h"
#include "engine/tpg/tpg.h"
#include "engine/tpg/tpg_replay.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kTpgHelp;
const char* const kTpgHelp =
    "usage: dashbench tpg --scene FILE --plan FILE [--out FILE] [--json] [--clearance M] [--rebuild] [--verbose]\n"
    "                     [--check N] [--seed S] [--max-wait S] [--max-stretch X] [--drop-edge K] [--threads N]\n"
    "The temporal plan graph of a valid plan (docs/dispatch.md): per arm, its motion segments and\n"
    "events; across arms, the edges an execution must respect (handovers, objects, swept volumes that\n"
    "meet within the clearance). The plan is validated first. A plan that carries a \"tpg\" field is\n"
    "read as it is (checked against the plan) unless --rebuild.\n"
    "  --out FILE       write the plan with its \"tpg\" field (dashbench.plan/1, docs/formats.md)\n"
    "  --json           print the graph (the \"tpg\" field) instead of the summary\n"
    "  --clearance M    parts closer than M metres meet (default 0.002, the planners' clearance)\n"
    "  --verbose        a line per cutting round of the build on standard error (pieces, pairs, evaluations);\n"
    "                   with --check, each failed draw's collisions and the node each arm was on then\n"
    "  --check N        replay N executions with random per-node delays that respect the graph and run\n"
    "                   the certified validator on each (draw 0: no delay); exit 1 if any fails\n"
    "  --seed S         first seed of the draws (default 1)\n"
    "  --max-wait S     a delayed node waits up to S seconds (default 2); half the nodes wait\n"
    "  --max-stretch X  every node runs 1 .. X times its planned duration (default 2)\n"
    "  --drop-edge K    check the graph without edge K, delaying only that edge's source node: shows the\n"
    "                   edge is needed when a draw fails\n"
    "Exit status: 0 fine, 1 the plan is invalid or a replay failed, 2 bad input.\n";

namespace {

void printSummary(const tpg::Graph& g, const Plan& plan, double seconds, const tpg::BuildStats& stats) {
  std::map<std::string, int> by_why;
  for (const tpg::Edge& e : g.edges) ++by_why[tpg::edgeWhyName(e.why)];
  std::printf("temporal plan graph of %s (clearance %.4g mm): %zu nodes, %zu edges (handover %d, object %d, swept %d)\n",
              plan.scene.c_str(), g.clearance * 1000.0, g.nodes.size(), g.edges.size(), by_why["handover"],
              by_why["object"], by_why["swept"]);
  for (std::size_t r = 0; r < g.robots.size(); ++r) {
    int motions = 0, events = 0;
    for (int i : g.armNodes(static_cast<int>(r))) {
      (g.nodes[static_cast<std::size_t>(i)].kind == tpg::Node::Kind::kEvent ? events : motions) += 1;
    }
    std::printf("  %s: %d motion segments, %d events\n", g.robots[r].c_str(), motions, events);
  }
  if (seconds > 0.0) {
    std::printf("built in %.2f s (%d pieces, %d cutting rounds, %d distance evaluations)\n", seconds, stats.pieces,
                stats.rounds, stats.evaluations);
  }
  if (g.forced > 0) {
    std::printf("warning: %d pairs of segments that run at once in the plan still meet at the finest cut; they are "
                "ordered by start (run --check)\n", g.forced);
  }
}

tpg::Graph graphOf(const Args& args, const Scene& scene, const Plan& plan) {
  tpg::BuildOptions options;
  options.clearance = args.number("clearance", options.clearance);
  if (!plan.tpg.empty() && !args.has("rebuild")) return tpg::parseTpg(plan.tpg, plan);
  tpg::BuildStats stats;
  const auto t0 = std::chrono::steady_clock::now();
  if (args.has("verbose")) {
    options.progress = [t0](const std::string& line) {
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::fprintf(stderr, "%8.2f s  %s\n", s, line.c_str());
    };
  }
  tpg::Graph g = tpg::buildGraph(scene, plan, options, &stats);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!args.has("json")) printSummary(g, plan, seconds, stats);
  const std::string problem = tpg::graphProblem(g, plan);
  DASH_DEMAND_MSG(problem.empty(), "the built graph is malformed: " + problem);
  return g;
}

/// One failed draw on standard error: its first geometric problems and, at each, every arm's node.
void printFailure(const tpg::Graph& g, int draw, const tpg::Timing& timing, const ValidationReport& v) {
  int shown = 0;
  for (const ValidationProblem& p : v.problems) {
    if (++shown > 3) break;
    std::fprintf(stderr, "draw %d: %s\n", draw, p.message.c_str());
    for (std::size_t r = 0; r < g.robots.size(); ++r) {
      for (int i : g.armNodes(static_cast<int>(r))) {
        const std::size_t n = static_cast<std::size_t>(i);
        if (timing.end[n] < p.t_closest - 1e-9) continue;
        const tpg::Node& node = g.nodes[n];
        const bool waiting = timing.start[n] > p.t_closest;
        std::fprintf(stderr, "  %s %s node %d (%s, planned %.3f .. %.3f s, replayed %.3f .. %.3f s)\n",
                     g.robots[r].c_str(), waiting ? "waiting for" : "on", i,
                     node.kind == tpg::Node::Kind::kEvent ? "event" : (node.moves ? "motion" : "hold"), node.t0,
                     node.t1, timing.start[n], timing.end[n]);
        break;
      }
    }
  }
}

int runCheck(const Args& args, const Scene& scene, const Plan& plan, tpg::Graph g, int threads) {
  tpg::ReplayOptions options;
  options.draws = static_cast<int>(args.integer("check", 100));
  options.seed = static_cast<std::uint64_t>(args.integer("seed", 1));
  options.max_wait = args.number("max-wait", options.max_wait);
  options.max_stretch = args.number("max-stretch", options.max_stretch);
  options.validation.threads = threads;
  if (args.has("verbose")) {
    options.on_failure = [&g](int draw, const tpg::Timing& timing, const ValidationReport& v) {
      printFailure(g, draw, timing, v);
    };
  }
  if (args.has("drop-edge")) {
    const long long k = args.integer("drop-edge", 0);
    if (k < 0 || k >= static_cast<long long>(g.edges.size())) {
      throw InputError("--drop-edge: the graph has " + std::to_string(g.edges.size()) + " edges (0 .. n-1)");
    }
    const tpg::Edge dropped = g.edges[static_cast<std::size_t>(k)];
    options.focus = dropped.from;
    g = tpg::withoutEdge(std::move(g), static_cast<std::size_t>(k));
    std::printf("without edge %lld (%s, node %d -> node %d); only node %d is delayed\n", k, tpg::edgeWhyName(dropped.why),
                dropped.from, dropped.to, dropped.from);
  }
  const tpg::ReplayReport r = tpg::checkReplays(scene, plan, g, options);
  std::printf("replays: %d draws, %d failed; makespan planned %.2f s, replayed %.2f .. %.2f s\n", r.draws, r.failed,
              r.planned_makespan, r.min_makespan, r.max_makespan);
  if (r.failed > 0) std::printf("first failure: draw %d: %s\n", r.first_failed_draw, r.first_problem.c_str());
  return r.failed == 0 ? kExitOk : kExitProblems;
}

}  // namespace

int runTpg(const std::vector<std::string>& words) {
  Args args(words, {.options = {"scene", "plan", "out", "clearance", "check", "seed", "max-wait", "max-stretch",
                                "drop-edge", "threads"},
                    .flags = {"json", "rebuild", "verbose"}});
  const Scene scene = loadScene(args.require("scene"), RobotLibrary::loadDefault());
  Plan plan = loadPlan(args.require("plan"));
  ValidationOptions validation;
  validation.threads = static_cast<int>(args.integer("threads", 0));
  const ValidationReport report = validatePlan(scene, plan, validation);
  if (!report.valid()) {
    std::fputs(report.summary().c_str(), stdout);
    std::printf("the plan is not valid: it has no temporal plan graph\n");
    return kExitProblems;
  }
  const tpg::Graph g = graphOf(args, scene, plan);
  if (args.has("json")) std::printf("%s\n", tpg::tpgToJson(g, plan).c_str());
  if (args.has("out")) {
    plan.tpg = tpg::tpgToJson(g, plan);
    savePlan(plan, args.require("out"));
    if (!args.has("json")) std::printf("wrote %s\n", args.require("out").c_str());
  }
  if (args.has("check")) return runCheck(args, scene, plan, g, validation.threads);
  return kExitOk;
}

}  // namespace dash::cli
