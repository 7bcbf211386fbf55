// UR5e kinematics throughput. Goals: >= 1,000,000 IK solves/s on one core (BM_UrIk, items/s);
// FK and body frames are on the collision-check hot path (well above 300k configurations/s with the
// collision check included). Run: build/bench_ik (median of 5 repetitions is reported).
#include <benchmark/benchmark.h>

#include <random>

#include "engine/robots/kinematics.h"

namespace dash {
namespace {

constexpr int kTargets = 1024;

const RobotModel& ur5e() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib->get("ur5e");
}

std::vector<JointVector> randomConfigurations(int n) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::vector<JointVector> qs;
  for (int i = 0; i < n; ++i) {
    JointVector q(6);
    for (int j = 0; j < 6; ++j) q[j] = angle(rng);
    qs.push_back(q);
  }
  return qs;
}

const Pose kBase = makePose(Vec3(0.2, -0.1, 0.05), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())));

void BM_UrIk(benchmark::State& state) {
  const RobotModel& m = ur5e();
  std::vector<Pose> targets;
  for (const auto& q : randomConfigurations(kTargets)) targets.push_back(forwardKinematics(m, kBase, q).X_WT);
  std::array<JointVector, kUrMaxIkSolutions> out;
  std::size_t i = 0;
  long solutions = 0;
  for (auto _ : state) {
    solutions += inverseKinematicsUr(m, kBase, targets[i], out);
    benchmark::DoNotOptimize(out);
    i = (i + 1) % targets.size();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["solutions_per_solve"] =
      benchmark::Counter(static_cast<double>(solutions) / static_cast<double>(state.iterations()));
}
BENCHMARK(BM_UrIk)->Repetitions(5)->ReportAggregatesOnly(true);

void BM_UrIkVector(benchmark::State& state) {
  const RobotModel& m = ur5e();
  std::vector<Pose> targets;
  for (const auto& q : randomConfigurations(kTargets)) targets.push_back(forwardKinematics(m, kBase, q).X_WT);
  std::size_t i = 0;
  for (auto _ : state) {
    auto sols = inverseKinematics(m, kBase, targets[i]);
    benchmark::DoNotOptimize(sols);
    i = (i + 1) % targets.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_UrIkVector)->Repetitions(5)->ReportAggregatesOnly(true);

void BM_UrFk(benchmark::State& state) {
  const RobotModel& m = ur5e();
  const auto qs = randomConfigurations(kTargets);
  std::size_t i = 0;
  for (auto _ : state) {
    FkResult fk = forwardKinematics(m, kBase, qs[i]);
    benchmark::DoNotOptimize(fk);
    i = (i + 1) % qs.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_UrFk)->Repetitions(5)->ReportAggregatesOnly(true);

void BM_UrBodyFrames(benchmark::State& state) {
  const RobotModel& m = ur5e();
  const auto qs = randomConfigurations(kTargets);
  std::vector<Pose> frames(m.bodies.size());
  std::size_t i = 0;
  for (auto _ : state) {
    bodyFrames(m, kBase, qs[i], frames);
    benchmark::DoNotOptimize(frames.data());
    benchmark::ClobberMemory();
    i = (i + 1) % qs.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_UrBodyFrames)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace
}  // namespace dash

BENCHMARK_MAIN();
