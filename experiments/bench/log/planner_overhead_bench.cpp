// Logging overhead with the real planners (issue "Results database": under 5 % of planning time).
// Each case (planner, scene, seed) is planned twice: once with a NullSink and once recorded into a
// results database (beginRun, SqliteRecorder, finishRun: everything a recorded run pays). The two
// runs of a pair are adjacent and alternate which goes first, so slow drifts of a shared machine
// cancel out. Per pair: wall-time ratio (recorded / null) and process-CPU ratio (every thread,
// the recorder's writer thread included). The summary prints the median ratios, over all pairs and
// over the pairs whose two runs did the same work (same iterations and sizes: the planners are
// seeded, but a deadline or timing-dependent choice can make the runs diverge).
//
//   build/bench_log_planners                       # the default cases (a few minutes)
//   build/bench_log_planners --benchmark_filter=lab
#include <benchmark/benchmark.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "engine/core/stopwatch.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"
#include "engine/planners/planner.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash::log {
namespace {

using KeyValues = std::vector<std::pair<std::string, std::string>>;

struct Case {
  std::string planner;
  std::string family;
  KeyValues params;
  std::uint64_t seed = 1;
  double time_limit = 120.0;

  std::string name() const {
    std::string n = planner + "/" + family;
    for (const auto& [k, v] : params) n += "_" + k + v;
    return n + "/seed" + std::to_string(seed);
  }
  std::string paramsJson() const {
    std::string j = "{";
    for (const auto& [k, v] : params) j += (j.size() > 1 ? "," : "") + ("\"" + k + "\":" + v);
    return j + "}";
  }
};

/// What one run cost and did.
struct Measured {
  bool done = false;
  double wall = 0.0;
  double cpu = 0.0;  ///< process CPU time, every thread
  std::int64_t events = 0;
  PlanOutcome outcome = PlanOutcome::kInfeasible;
  int iterations = 0;
  RepresentationCounts sizes;
};

struct Pair {
  Measured null_sink, recorded;
};

struct Bench {
  std::vector<Case> cases;
  std::map<std::string, Pair> results;
  std::map<std::string, Scene> scenes;
  std::string db_path;
};

double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

const Scene& sceneOf(Bench& bench, const Case& c) {
  const std::string key = c.family + c.paramsJson() + std::to_string(c.seed);
  auto it = bench.scenes.find(key);
  if (it == bench.scenes.end())
    it = bench.scenes.emplace(key, generateScenario(c.family, c.params, c.seed, RobotLibrary::loadDefault())).first;
  return it->second;
}

Measured runOnce(Bench& bench, const Case& c, bool record) {
  const Scene& scene = sceneOf(bench, c);
  PlannerSettings settings;
  settings.seed = c.seed;
  settings.time_limit = c.time_limit;
  auto planner = makePlanner(c.planner);
  Measured m;
  const double cpu0 = processCpuSeconds();
  const Stopwatch clock;
  PlanResult result;
  if (record) {
    ResultsDb db(bench.db_path);
    const std::string uuid = db.beginRun(RunMetadata{.family = c.family,
                                                     .params_json = c.paramsJson(),
                                                     .seed = c.seed,
                                                     .planner = c.planner,
                                                     .time_limit = c.time_limit});
    {
      auto recorder = db.recorder(uuid);
      result = planner->solve(scene, settings, Deadline(c.time_limit), recorder.get());
      m.events = recorder->acceptedEvents();
    }
    db.finishRun(uuid, RunSummary{.status = result.outcome == PlanOutcome::kSolved ? RunStatus::Solved
                                                                                  : RunStatus::Timeout});
  } else {
    NullSink sink;
    result = planner->solve(scene, settings, Deadline(c.time_limit), &sink);
  }
  m.wall = clock.seconds();
  m.cpu = processCpuSeconds() - cpu0;
  m.done = true;
  m.outcome = result.outcome;
  m.iterations = result.stats.iterations;
  m.sizes = result.stats.sizes;
  return m;
}

bool sameWork(const Measured& a, const Measured& b) {
  const RepresentationCounts &x = a.sizes, &y = b.sizes;
  return a.outcome == b.outcome && a.iterations == b.iterations && x.task_vertices == y.task_vertices &&
         x.task_hyperarcs == y.task_hyperarcs && x.task_extended_vertices == y.task_extended_vertices &&
         x.task_extended_hyperarcs == y.task_extended_hyperarcs && x.motion_vertices == y.motion_vertices &&
         x.motion_hyperarcs == y.motion_hyperarcs && x.motion_extended_vertices == y.motion_extended_vertices &&
         x.motion_extended_hyperarcs == y.motion_extended_hyperarcs;
}

void benchRun(benchmark::State& state, Bench* bench, const Case* c, bool record) {
  for (auto _ : state) {
    const Measured m = runOnce(*bench, *c, record);
    state.SetIterationTime(m.wall);
    Pair& pair = bench->results[c->name()];
    (record ? pair.recorded : pair.null_sink) = m;
    state.counters["cpu_s"] = m.cpu;
    state.counters["events"] = static_cast<double>(m.events);
    state.counters["solved"] = m.outcome == PlanOutcome::kSolved ? 1 : 0;
  }
}

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

void printSummary(const Bench& bench) {
  std::printf("\n%-44s %8s %8s %8s %8s %9s %8s %5s\n", "case", "null s", "rec s", "wall x", "cpu x", "events",
              "outcome", "same");
  std::vector<double> wall_all, cpu_all, wall_same, cpu_same;
  for (const Case& c : bench.cases) {
    const auto it = bench.results.find(c.name());
    if (it == bench.results.end() || !it->second.null_sink.done || !it->second.recorded.done) continue;
    const Pair& p = it->second;
    const double wall = p.recorded.wall / p.null_sink.wall;
    const double cpu = p.recorded.cpu / p.null_sink.cpu;
    const bool same = sameWork(p.null_sink, p.recorded);
    wall_all.push_back(wall);
    cpu_all.push_back(cpu);
    if (same) {
      wall_same.push_back(wall);
      cpu_same.push_back(cpu);
    }
    std::printf("%-44s %8.2f %8.2f %8.3f %8.3f %9lld %8s %5s\n", c.name().c_str(), p.null_sink.wall,
                p.recorded.wall, wall, cpu, static_cast<long long>(p.recorded.events), toString(p.recorded.outcome),
                same ? "yes" : "no");
  }
  std::printf("median ratio recorded/null over %zu pairs: wall %.3f, cpu %.3f\n", wall_all.size(), median(wall_all),
              median(cpu_all));
  std::printf("median ratio over the %zu pairs that did the same work: wall %.3f, cpu %.3f\n", wall_same.size(),
              median(wall_same), median(cpu_same));
}

std::vector<Case> defaultCases() {
  std::vector<Case> cases;
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    cases.push_back({"lazy-dash", "sorting", {{"robots", "4"}, {"objects", "8"}}, seed});
  for (std::uint64_t seed = 1; seed <= 3; ++seed) cases.push_back({"lazy-dash", "lab", {{"containers", "2"}}, seed});
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
    cases.push_back({"dash", "sorting", {{"robots", "4"}, {"objects", "4"}}, seed});
  return cases;
}

}  // namespace
}  // namespace dash::log

int main(int argc, char** argv) {
  using namespace dash::log;
  Bench bench;
  bench.cases = defaultCases();
  const auto dir = std::filesystem::temp_directory_path() / ("dashbench-bench-planners-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  bench.db_path = (dir / "results.db").string();
  int index = 0;
  for (const Case& c : bench.cases) {
    // Alternate which run of a pair goes first.
    const bool recorded_first = (index++ % 2) == 1;
    for (const bool record : {recorded_first, !recorded_first}) {
      benchmark::RegisterBenchmark((c.name() + (record ? "/sqlite" : "/null")).c_str(), benchRun, &bench, &c, record)
          ->Iterations(1)
          ->UseManualTime()
          ->Unit(benchmark::kSecond);
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  printSummary(bench);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return 0;
}
