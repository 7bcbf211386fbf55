// Scenario generation time, validation included (check-scene logic, handover graph, per-object
// chains). Goal: the largest Sorting scene (32 robots, 128 objects) in under 10 s. Run:
// build/bench_scenarios.
#include <benchmark/benchmark.h>

#include "engine/scenarios/scenario_registry.h"
#include "engine/scene/scene_json.h"

namespace dash {
namespace {

const std::shared_ptr<const RobotLibrary>& library() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib;
}

void generate(benchmark::State& state, const std::string& family,
              const std::vector<std::pair<std::string, std::string>>& params) {
  std::uint64_t seed = 0;
  for (auto _ : state) {
    const Scene scene = generateScenario(family, params, seed++, library());
    benchmark::DoNotOptimize(scene.objects.data());
  }
  state.counters["seconds_goal"] = 10.0;
}

void BM_SortingLargest(benchmark::State& state) { generate(state, "sorting", {{"robots", "32"}, {"objects", "128"}}); }
BENCHMARK(BM_SortingLargest)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_SortingLargestToJson(benchmark::State& state) {
  const Scene scene = generateScenario("sorting", {{"robots", "32"}, {"objects", "128"}}, 1, library());
  for (auto _ : state) benchmark::DoNotOptimize(sceneToJson(scene));
}
BENCHMARK(BM_SortingLargestToJson)->Unit(benchmark::kMillisecond);

void BM_WallLargest(benchmark::State& state) {
  generate(state, "wall", {{"robots", "32"}, {"walls", "6"}, {"objects", "128"}});
}
BENCHMARK(BM_WallLargest)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_ShelfWallLargest(benchmark::State& state) {
  generate(state, "shelf-wall", {{"robots", "8"}, {"objects", "32"}});
}
BENCHMARK(BM_ShelfWallLargest)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_StockingLargest(benchmark::State& state) { generate(state, "stocking", {{"layers", "3"}, {"objects", "28"}}); }
BENCHMARK(BM_StockingLargest)->Unit(benchmark::kMillisecond)->Iterations(5);

void BM_LabLargest(benchmark::State& state) { generate(state, "lab", {{"containers", "24"}}); }
BENCHMARK(BM_LabLargest)->Unit(benchmark::kMillisecond)->Iterations(5);

}  // namespace
}  // namespace dash

BENCHMARK_MAIN();
