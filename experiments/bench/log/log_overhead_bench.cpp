// Logging overhead: the same stream of 100k planner events through no sink, the null sink, the
// in-memory sink and the SQLite recorder. Reports events/s; the per-event cost of recording is
// (recorder time - null-sink time) / events. The planning-time ratio is measured with real
// planners (issue "Results database": under 5 % of planning time).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>

#include "engine/events/event_emitter.h"
#include "engine/events/memory_sink.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"

namespace dash::log {
namespace {

constexpr int kEvents = 100'000;

// A stream shaped like a planner's: 25 % vertices, 30 % hyperarcs (1-3 head and tail ids), 10 %
// constraints, 1 % task space expansions, 14 % phase boundaries, 20 % counters.
const std::vector<EventPayload>& stream() {
  static const std::vector<EventPayload> payloads = [] {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> percent(0, 99), small(1, 3);
    std::uniform_int_distribution<std::uint32_t> id(0, 50'000);
    const char* arc_types[] = {"pick", "place", "handover", "transition", "move"};
    const char* counters[] = {"collision_checks_eager", "collision_checks_lazy", "roadmap_vertices", "roadmap_edges"};
    // Built in place (emplace<T>): moving these variants around trips a GCC 12 -O3
    // -Wmaybe-uninitialized false positive.
    std::vector<EventPayload> out(kEvents);
    std::int64_t counter_value = 0;
    int open_phase = -1;
    for (int i = 0; i < kEvents; ++i) {
      const int p = percent(rng);
      const Layer layer = static_cast<Layer>(i % kLayerCount);
      if (p < 25) {
        auto& v = out[i].emplace<RepresentationEvent>();
        v.layer = layer;
        v.id = id(rng);
        v.label = "R" + std::to_string(small(rng)) + "+O" + std::to_string(id(rng) % 64);
      } else if (p < 55) {
        auto& a = out[i].emplace<RepresentationEvent>();
        a.layer = layer;
        a.kind = ElementKind::Hyperarc;
        a.arc_type = arc_types[p % 5];
        a.id = id(rng);
        a.head.resize(small(rng));
        a.tail.resize(small(rng));
        for (auto& v : a.head) v = id(rng);
        for (auto& v : a.tail) v = id(rng);
        a.label = "R1 picks O3";
      } else if (p < 65) {
        auto& c = out[i].emplace<ConstraintEvent>();
        c.kind = ConstraintKind::History;
        c.id = id(rng);
        c.content = "(v_pre=12, v_post=40)";
        c.vertices = {id(rng), id(rng)};
        c.conflict = "grasp of R2 collides with O7";
      } else if (p < 66) {
        out[i].emplace<TaskSpaceExpansionEvent>(TaskSpaceExpansionEvent{3, "O3", "stable pose 9", "constraints contradict"});
      } else if (p < 80) {
        // Alternate start/end so that intervals are well formed.
        auto& ph = out[i].emplace<PhaseEvent>();
        if (open_phase < 0) {
          open_phase = p % kPhaseCount;
          ph.phase = static_cast<Phase>(open_phase);
        } else {
          ph = PhaseEvent{static_cast<Phase>(open_phase), PhaseBoundary::End, 1e-4};
          open_phase = -1;
        }
      } else {
        out[i].emplace<CounterEvent>(CounterEvent{counters[p % 4], counter_value += 17});
      }
    }
    return out;
  }();
  return payloads;
}

void emitAll(EventEmitter& em) {
  int n = 0;
  for (const EventPayload& p : stream()) {
    if ((++n & 1023) == 0) em.setIteration(n >> 10);
    em.emit(p);  // a copy, as a planner constructs each event
  }
}

void BM_NoSink(benchmark::State& state) {
  EventEmitter em(nullptr);
  for (auto _ : state) {
    for (const EventPayload& p : stream()) {
      EventPayload copy = p;  // the planner still builds the event
      benchmark::DoNotOptimize(copy);
      em.emit(std::move(copy));
    }
  }
  state.SetItemsProcessed(state.iterations() * kEvents);
}

void BM_NullSink(benchmark::State& state) {
  NullSink sink;
  EventEmitter em(&sink);
  for (auto _ : state) emitAll(em);
  state.SetItemsProcessed(state.iterations() * kEvents);
}

void BM_MemorySink(benchmark::State& state) {
  for (auto _ : state) {
    MemorySink sink;
    EventEmitter em(&sink);
    emitAll(em);
    state.PauseTiming();
    sink.clear();
    state.ResumeTiming();
  }
  state.SetItemsProcessed(state.iterations() * kEvents);
}

// One run per iteration into a fresh file; state.range(0) = events per batch. With
// state.range(1) == 0 the timing stops when the last event is emitted (the planner thread's cost:
// the writer thread works on another core); with 1 it includes waiting until everything is
// committed (the whole cost, for a machine with no spare core).
void BM_SqliteRecorder(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / "dashbench-bench-log";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "bench.db").string();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  const bool until_committed = state.range(1) != 0;
  {
    ResultsDb db(path, OpenMode::ReadWrite, DbOptions{.batch_events = static_cast<int>(state.range(0))});
    RunMetadata meta{.family = "sorting", .params_json = R"({"robots":4,"objects":16})", .planner = "lazy-dash"};
    for (auto _ : state) {
      state.PauseTiming();
      const std::string uuid = db.beginRun(meta);
      auto recorder = db.recorder(uuid);
      EventEmitter em(recorder.get());
      state.ResumeTiming();
      emitAll(em);
      if (until_committed) db.flush();
      state.PauseTiming();
      db.finishRun(uuid, RunSummary{});
      state.ResumeTiming();
    }
  }
  state.counters["MB_per_run"] = benchmark::Counter(
      static_cast<double>(std::filesystem::file_size(path)) / 1e6 / static_cast<double>(state.iterations()));
  state.SetItemsProcessed(state.iterations() * kEvents);
  std::filesystem::remove_all(dir);
}

void BM_SqliteRecorderAllThreadsCpu(benchmark::State& state) { BM_SqliteRecorder(state); }

// finishRun alone on a run of 100k events (the writer's tally: no aggregate queries over them).
void BM_FinishRun(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / "dashbench-bench-finish";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "bench.db").string();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  {
    ResultsDb db(path);
    RunMetadata meta{.family = "sorting", .params_json = R"({"robots":4})", .planner = "lazy-dash"};
    for (auto _ : state) {
      state.PauseTiming();
      const std::string uuid = db.beginRun(meta);
      {
        auto recorder = db.recorder(uuid);
        EventEmitter em(recorder.get());
        emitAll(em);
      }
      db.flush();
      state.ResumeTiming();
      db.finishRun(uuid, RunSummary{});
    }
  }
  std::filesystem::remove_all(dir);
}

// The fixed cost of a recorded run, whatever it emits: beginRun, a recorder, one event, finishRun
// (two transactions), on a database opened once (as the batch runner does).
void BM_EmptyRun(benchmark::State& state) {
  const auto dir = std::filesystem::temp_directory_path() / "dashbench-bench-empty";
  std::filesystem::create_directories(dir);
  const std::string path = (dir / "bench.db").string();
  for (const char* suffix : {"", "-wal", "-shm"}) std::filesystem::remove(path + suffix);
  {
    ResultsDb db(path);
    RunMetadata meta{.family = "sorting", .params_json = R"({"robots":4})", .planner = "lazy-dash"};
    for (auto _ : state) {
      const std::string uuid = db.beginRun(meta);
      {
        auto recorder = db.recorder(uuid);
        EventEmitter em(recorder.get());
        em.vertex(Layer::Task, 0, "R1");
      }
      db.finishRun(uuid, RunSummary{});
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace

BENCHMARK(BM_NoSink)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_NullSink)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_MemorySink)->Unit(benchmark::kMillisecond);
// CPU column: the planner thread only (the writer thread's work is not in it).
BENCHMARK(BM_SqliteRecorder)
    ->ArgNames({"batch", "until_committed"})
    ->Args({4096, 0})
    ->Args({4096, 1})
    ->Args({256, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);
// CPU column: every thread (planner and writer), i.e. the recorder's whole cost.
BENCHMARK(BM_SqliteRecorderAllThreadsCpu)
    ->ArgNames({"batch", "until_committed"})
    ->Args({4096, 1})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->MinTime(2.0);
BENCHMARK(BM_FinishRun)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK(BM_EmptyRun)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime();

}  // namespace dash::log

BENCHMARK_MAIN();
