// Logging overhead with the real planners (issue "Results database": under 5 % of planning time).
// Each case (planner, scene, seed) is planned twice: once with a NullSink and once recorded into a
// results database (beginRun, SqliteRecorder, finishRun: everything a recorded run pays; the
// database is opened once, as the batch runner does). The two runs of a pair are adjacent and
// alternate which goes first, so slow drifts of a shared machine cancel out. Per pair, ratios
// recorded / null of: wall time; process CPU time (every thread, the recorder's writer thread
// included: what a machine without a spare core pays); and the planner thread's CPU time (what
// recording costs the planner itself when the writer thread has a core of its own). The summary
// prints the median ratios, over all pairs and over the pairs whose two runs did the same work
// (same iterations and sizes: the planners are seeded, but a deadline or timing-dependent choice
// can make the runs diverge: Lazy-DaSH on sorting 4x8 sometimes takes a path that emits a million
// events and sometimes not, whatever the sink).
//
// The summary also splits the pairs by size: ordinary runs (hundreds to thousands of events) and
// event-heavy runs (100k events or more: Lazy-DaSH runs whose task queries explore a lot, e.g.
// stocking 3 layers 12 objects, and a synthetic burst shaped like the densest of them: 1M
// task-extended vertices and hyperarcs with labels and ids, each after about a microsecond of
// planner-like CPU work).
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
#include <memory>
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

/// Not a planner: the synthetic event burst (syntheticBurst).
constexpr const char* kBurst = "synthetic-burst";

struct Case {
  std::string planner;  ///< a planner name, or kBurst
  std::string family;
  KeyValues params;
  std::uint64_t seed = 1;
  double time_limit = 120.0;
  bool task_only = false;  ///< Lazy-DaSH: the task layer alone

  std::string name() const {
    std::string n = planner + (task_only ? "-task-only" : "") + "/" + family;
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
  double planner_cpu = 0.0;  ///< this thread's CPU time: the planner and what recording costs it
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
  /// Opened once, as the batch runner opens its database once per batch (server/batch).
  std::unique_ptr<ResultsDb> db;
};

double cpuSeconds(clockid_t clock) {
  timespec ts{};
  clock_gettime(clock, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
double processCpuSeconds() { return cpuSeconds(CLOCK_PROCESS_CPUTIME_ID); }
double threadCpuSeconds() { return cpuSeconds(CLOCK_THREAD_CPUTIME_ID); }

const Scene& sceneOf(Bench& bench, const Case& c) {
  const std::string key = c.family + c.paramsJson() + std::to_string(c.seed);
  auto it = bench.scenes.find(key);
  if (it == bench.scenes.end())
    it = bench.scenes.emplace(key, generateScenario(c.family, c.params, c.seed, RobotLibrary::loadDefault())).first;
  return it->second;
}

/// A planner-like burst: per step some CPU work (a dependent integer chain: no memory traffic, no
/// sleeping), then the events a Lazy-DaSH task query emits for an extended vertex and its hyperarcs
/// (labels and head/tail vectors built per event, as the planner builds them). 1M events.
PlanResult syntheticBurst(EventSink* sink, std::uint64_t seed) {
  constexpr int kSteps = 400'000;        // 2.5 events per step
  constexpr int kWorkPerEvent = 700;     // chain steps: about 1.3 us of CPU per event on this machine
  EventEmitter emitter(sink);
  std::uint64_t x = seed * 0x9E3779B97F4A7C15ULL + 1;
  auto work = [&](int n) {
    for (int k = 0; k < n; ++k) x = (x ^ (x >> 29)) * 0xBF58476D1CE4E5B9ULL + 0x94D049BB133111EBULL;
    return x;
  };
  const char* arc_types[] = {"pick", "place", "handover", "composition"};
  std::uint32_t vertices = 0, hyperarcs = 0;
  PlanResult result;
  {
    PhaseTimer query(emitter, Phase::TaskQuery);
    for (int step = 0; step < kSteps; ++step) {
      if (step % 2000 == 0) emitter.setIteration(step / 2000);
      work(kWorkPerEvent);
      emitter.vertex(Layer::TaskExtended, vertices++,
                     "R" + std::to_string(x % 4) + "+O" + std::to_string((x >> 8) % 18) + "@s" + std::to_string((x >> 16) % 40));
      const int arcs = 1 + static_cast<int>((x >> 24) % 2) + (step % 2);  // 1-3, 1.5 on average
      for (int a = 0; a < arcs; ++a) {
        work(kWorkPerEvent);
        std::vector<std::uint32_t> head{vertices - 1};
        std::vector<std::uint32_t> tail{static_cast<std::uint32_t>(x % vertices)};
        if ((x >> 32) % 3 == 0) tail.push_back(static_cast<std::uint32_t>((x >> 40) % vertices));
        emitter.hyperarc(Layer::TaskExtended, arc_types[(x >> 20) % 4], hyperarcs++, std::move(head), std::move(tail));
      }
      if (step % 1000 == 999) emitter.counter("collision_checks_lazy", step * 3);
    }
  }
  result.outcome = PlanOutcome::kInfeasible;
  result.stats.sizes.task_extended_vertices = vertices;
  result.stats.sizes.task_extended_hyperarcs = hyperarcs;
  result.stats.iterations = kSteps / 2000;
  return result;
}

Measured runOnce(Bench& bench, const Case& c, bool record) {
  const bool burst = c.planner == kBurst;
  const Scene* scene = burst ? nullptr : &sceneOf(bench, c);
  PlannerSettings settings;
  settings.seed = c.seed;
  settings.time_limit = c.time_limit;
  settings.task_only = c.task_only;
  auto planner = burst ? nullptr : makePlanner(c.planner);
  auto solve = [&](EventSink* sink) {
    return burst ? syntheticBurst(sink, c.seed) : planner->solve(*scene, settings, Deadline(c.time_limit), sink);
  };
  Measured m;
  const double cpu0 = processCpuSeconds();
  const double thread0 = threadCpuSeconds();
  const Stopwatch clock;
  PlanResult result;
  if (record) {
    ResultsDb& db = *bench.db;
    const std::string uuid = db.beginRun(RunMetadata{.family = c.family,
                                                     .params_json = c.paramsJson(),
                                                     .seed = c.seed,
                                                     .planner = c.planner,
                                                     .time_limit = c.time_limit});
    {
      auto recorder = db.recorder(uuid);
      result = solve(recorder.get());
      m.events = recorder->acceptedEvents();
    }
    db.finishRun(uuid, RunSummary{.status = result.outcome == PlanOutcome::kSolved ? RunStatus::Solved
                                                                                  : RunStatus::Timeout});
  } else {
    NullSink sink;
    result = solve(&sink);
  }
  m.wall = clock.seconds();
  m.cpu = processCpuSeconds() - cpu0;
  m.planner_cpu = threadCpuSeconds() - thread0;
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
    state.counters["planner_cpu_s"] = m.planner_cpu;
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

/// A recorded run with at least this many events counts as event-heavy in the summary.
constexpr std::int64_t kHeavyEvents = 100'000;

/// Wall, process-CPU and planner-thread-CPU ratios of a set of pairs.
struct Ratios {
  std::vector<double> wall, cpu, planner;
  void add(double w, double c, double p) {
    wall.push_back(w);
    cpu.push_back(c);
    planner.push_back(p);
  }
  void print(const char* what) const {
    std::printf("median ratio recorded/null over %zu %s: wall %.3f, cpu %.3f, planner thread cpu %.3f\n", wall.size(),
                what, median(wall), median(cpu), median(planner));
  }
};

// Columns: the wall time of each run, then the ratios recorded/null of wall time, of the process's
// CPU time (every thread: what a machine with no spare core pays), and of the planner thread's own
// CPU time (what recording costs the planner when the writer thread has a core of its own).
void printSummary(const Bench& bench) {
  std::printf("\n%-52s %8s %8s %8s %8s %8s %9s %8s %5s\n", "case", "null s", "rec s", "wall x", "cpu x", "thread x",
              "events", "outcome", "same");
  Ratios all, same_work, ordinary, heavy;
  for (const Case& c : bench.cases) {
    const auto it = bench.results.find(c.name());
    if (it == bench.results.end() || !it->second.null_sink.done || !it->second.recorded.done) continue;
    const Pair& p = it->second;
    const double wall = p.recorded.wall / p.null_sink.wall;
    const double cpu = p.recorded.cpu / p.null_sink.cpu;
    const double planner = p.recorded.planner_cpu / p.null_sink.planner_cpu;
    const bool same = sameWork(p.null_sink, p.recorded);
    all.add(wall, cpu, planner);
    if (same) same_work.add(wall, cpu, planner);
    (p.recorded.events >= kHeavyEvents ? heavy : ordinary).add(wall, cpu, planner);
    std::printf("%-52s %8.3f %8.3f %8.3f %8.3f %8.3f %9lld %8s %5s\n", c.name().c_str(), p.null_sink.wall,
                p.recorded.wall, wall, cpu, planner, static_cast<long long>(p.recorded.events),
                toString(p.recorded.outcome), same ? "yes" : "no");
  }
  all.print("pairs");
  same_work.print("pairs that did the same work");
  ordinary.print("pairs under 100k events");
  heavy.print("event-heavy pairs (100k events or more)");
}

std::vector<Case> defaultCases() {
  std::vector<Case> cases;
  for (std::uint64_t seed = 1; seed <= 5; ++seed)
    cases.push_back({"lazy-dash", "sorting", {{"robots", "4"}, {"objects", "8"}}, seed});
  for (std::uint64_t seed = 1; seed <= 3; ++seed) cases.push_back({"lazy-dash", "lab", {{"containers", "2"}}, seed});
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
    cases.push_back({"dash", "sorting", {{"robots", "4"}, {"objects", "4"}}, seed});
  // Event-heavy: the synthetic burst, and real runs whose task query explores a lot.
  for (std::uint64_t seed = 1; seed <= 3; ++seed)
    cases.push_back({kBurst, "synthetic", {{"events", "1000000"}}, seed});
  cases.push_back({"lazy-dash", "stocking", {{"layers", "3"}, {"objects", "12"}}, 1, 60.0});
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
  bench.db = std::make_unique<ResultsDb>(bench.db_path);
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
  bench.db.reset();
  printSummary(bench);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return 0;
}
