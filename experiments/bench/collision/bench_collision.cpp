// One UR5e configuration, forward kinematics plus the full collision check (self pairs and obstacles),
// against 20 random boxes around the robot (fixed seed; 90% of the configurations are collision-free).
// Goal: >= 300,000 configurations/s on one core (BM_CollisionWorld, median items/s).
// Baselines in the same binary, on the same configurations:
//  - BM_NaiveFcl: every body against every box and every self pair through fcl::collide, no pre-check;
//  - BM_FclBroadphase: robot bodies as fcl::CollisionObjects (setTransform + computeAABB) against a
//    DynamicAABBTreeCollisionManager of the boxes, self pairs through fcl::collide.
//  - BM_CoverBatch (issue 38): the vectorised check, 8 configurations at a time: batched forward
//    kinematics and the link covers (engine/collision/cover_check.h) against the boxes and self pairs;
//    the configurations the covers cannot clear go to CollisionWorld's exact check. Goal: >= 5 M
//    configurations/s on one core, >= 50x the FCL broad phase.
//  - BM_CollisionWorldNoCover: CollisionWorld with the covers' fast reject off (DASHBENCH_COVER=off),
//    the exact check alone, as before issue 38.
// Every baseline must agree with CollisionWorld on every configuration (checked before timing).
// Run: build/bench_collision (5 repetitions, median reported, ratios printed at the end).
#include <benchmark/benchmark.h>

#include <cstdio>
#include <fcl/broadphase/broadphase_dynamic_AABB_tree.h>
#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <map>
#include <memory>
#include <string>

#include "engine/collision/collision_queries.h"
#include "engine/collision/cover_check.h"
#include "engine/core/rng.h"
#include "engine/robots/kinematics.h"

namespace dash {
namespace {

constexpr int kBoxes = 20;
constexpr int kConfigurations = 1024;
constexpr double kFreeShare = 0.9;
constexpr std::uint64_t kSeed = 2024;

/// A UR5e at the origin and 20 boxes (5-20 cm edges, any yaw) 0.3-1.1 m from its base axis, 0-1 m up.
const Scene& benchScene() {
  static const Scene scene = [] {
    Scene s;
    s.name = "bench-20-boxes";
    s.library = RobotLibrary::loadDefault();
    SceneRobot r;
    r.id = "ur5e_0";
    r.model_name = "ur5e";
    r.model = s.library->find("ur5e");
    r.home = JointVector::Zero(6);
    r.capabilities = {"grasp"};
    s.robots.push_back(r);
    Rng rng(kSeed);
    for (int i = 0; i < kBoxes; ++i) {
      const double radius = rng.uniform(0.3, 1.1);
      const double heading = rng.uniform(-M_PI, M_PI);
      const Vec3 p(radius * std::cos(heading), radius * std::sin(heading), rng.uniform(0.0, 1.0));
      const Vec3 size(rng.uniform(0.05, 0.2), rng.uniform(0.05, 0.2), rng.uniform(0.05, 0.2));
      s.obstacles.push_back({.id = "box_" + std::to_string(i), .shape = BoxShape{size},
                             .X_WO = makePose(p, Quat(Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), Vec3::UnitZ())))});
    }
    return s;
  }();
  return scene;
}

const CollisionWorld& benchWorld() {
  static const CollisionWorld world(benchScene());
  return world;
}

/// 1024 configurations in [-pi, pi]^6: 90% collision-free, the rest colliding, shuffled.
const std::vector<JointVector>& benchConfigurations() {
  static const std::vector<JointVector> configurations = [] {
    CollisionContext context(benchWorld());
    const ObjectLayout none = ObjectLayout::empty(benchScene());
    Rng rng(kSeed + 1);
    std::vector<JointVector> free, hit;
    const auto want_free = static_cast<std::size_t>(kFreeShare * kConfigurations);
    while (free.size() < want_free || hit.size() < kConfigurations - want_free) {
      JointVector q(6);
      for (int j = 0; j < 6; ++j) q[j] = rng.uniform(-M_PI, M_PI);
      auto& bucket = robotInCollision(benchWorld(), context, {.robot = 0, .q = q}, none) ? hit : free;
      if (bucket.size() < (&bucket == &free ? want_free : kConfigurations - want_free)) bucket.push_back(q);
    }
    std::vector<JointVector> all;
    for (std::size_t i = 0; i < free.size(); ++i) {
      all.push_back(free[i]);
      if (i % 9 == 8 && i / 9 < hit.size()) all.push_back(hit[i / 9]);
    }
    for (std::size_t k = all.size() - free.size(); k < hit.size(); ++k) all.push_back(hit[k]);
    return all;
  }();
  return configurations;
}

// ---- baselines -----------------------------------------------------------------------------------

/// Shapes of the robot bodies and boxes, for the plain FCL loops.
struct FclScene {
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> body_shapes;
  std::vector<Pose> X_FG;
  std::vector<std::shared_ptr<fcl::CollisionGeometryd>> box_shapes;
  std::vector<Pose> X_WO;
};

const FclScene& fclScene() {
  static const FclScene f = [] {
    FclScene out;
    const CollisionWorld& world = benchWorld();
    for (const BodyGeometry& g : world.robot(0).bodies) {
      out.body_shapes.push_back(std::const_pointer_cast<fcl::CollisionGeometryd>(g.shape));
      out.X_FG.push_back(g.X_FG);
    }
    for (const ObstacleGeometry& o : world.obstacles()) {
      out.box_shapes.push_back(std::const_pointer_cast<fcl::CollisionGeometryd>(o.shape));
      out.X_WO.push_back(o.X_WO);
    }
    return out;
  }();
  return f;
}

bool collides(const fcl::CollisionGeometryd& a, const Pose& X_a, const fcl::CollisionGeometryd& b, const Pose& X_b) {
  const fcl::CollisionRequestd request;
  fcl::CollisionResultd result;
  return fcl::collide(&a, X_a, &b, X_b, request, result) > 0;
}

bool selfPairsCollide(const RobotModel& m, const FclScene& f, const std::vector<Pose>& X_WG) {
  for (const auto& [b1, b2] : m.self_collision_pairs) {
    if (collides(*f.body_shapes[b1], X_WG[b1], *f.body_shapes[b2], X_WG[b2])) return true;
  }
  return false;
}

/// Every body against every box and every self pair, no pre-check.
struct NaiveChecker {
  const RobotModel& model = *benchScene().robots[0].model;
  const FclScene& f = fclScene();
  std::vector<Pose> frames = std::vector<Pose>(model.bodies.size());
  std::vector<Pose> X_WG = std::vector<Pose>(model.bodies.size());

  bool operator()(const JointVector& q) {
    bodyFrames(model, Pose::Identity(), q, frames);
    for (std::size_t b = 0; b < frames.size(); ++b) X_WG[b] = frames[b] * f.X_FG[b];
    for (std::size_t b = 0; b < X_WG.size(); ++b) {
      for (std::size_t i = 0; i < f.box_shapes.size(); ++i) {
        if (collides(*f.body_shapes[b], X_WG[b], *f.box_shapes[i], f.X_WO[i])) return true;
      }
    }
    return selfPairsCollide(model, f, X_WG);
  }
};

/// FCL's own broad phase: a dynamic AABB tree of the boxes, body objects moved each query.
struct BroadphaseChecker {
  const RobotModel& model = *benchScene().robots[0].model;
  const FclScene& f = fclScene();
  std::vector<Pose> frames = std::vector<Pose>(model.bodies.size());
  std::vector<Pose> X_WG = std::vector<Pose>(model.bodies.size());
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> boxes;
  std::vector<std::unique_ptr<fcl::CollisionObjectd>> bodies;
  fcl::DynamicAABBTreeCollisionManagerd manager;

  BroadphaseChecker() {
    for (std::size_t i = 0; i < f.box_shapes.size(); ++i) {
      boxes.push_back(std::make_unique<fcl::CollisionObjectd>(f.box_shapes[i], f.X_WO[i]));
      manager.registerObject(boxes.back().get());
    }
    manager.setup();
    for (const auto& shape : f.body_shapes) bodies.push_back(std::make_unique<fcl::CollisionObjectd>(shape));
  }

  struct Data {
    bool hit = false;
  };
  static bool callback(fcl::CollisionObjectd* a, fcl::CollisionObjectd* b, void* raw) {
    auto* data = static_cast<Data*>(raw);
    const fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    if (fcl::collide(a, b, request, result) > 0) data->hit = true;
    return data->hit;  // true stops the traversal
  }

  bool operator()(const JointVector& q) {
    bodyFrames(model, Pose::Identity(), q, frames);
    for (std::size_t b = 0; b < frames.size(); ++b) {
      X_WG[b] = frames[b] * f.X_FG[b];
      bodies[b]->setTransform(X_WG[b]);
      bodies[b]->computeAABB();
      Data data;
      manager.collide(bodies[b].get(), &data, callback);
      if (data.hit) return true;
    }
    return selfPairsCollide(model, f, X_WG);
  }
};

/// The vectorised check: kBatchLanes configurations through the covers; the lanes they cannot clear
/// through the exact check.
struct CoverChecker {
  const CollisionWorld& world = benchWorld();
  CollisionContext context{world};
  const ObjectLayout none = ObjectLayout::empty(benchScene());
  JointBatch q;
  FrameBatch frames;
  detail::RobotCoverBatch cover;
  int exact_checks = 0;

  CoverChecker() { detail::prepareResting(world, context, none, {}); }

  /// answers[l] for configurations qs[0 .. kBatchLanes).
  void operator()(const JointVector* qs, bool* answers) {
    for (int l = 0; l < kBatchLanes; ++l) q.set(l, qs[l]);
    batchFrames(*world.robot(0).model, world.robot(0).robot->X_WB, q, frames);
    detail::coverFromFrames(world, 0, frames, HeldObject{}, cover);
    alignas(64) double clear[kBatchLanes];
    std::fill_n(clear, kBatchLanes, 1.0);
    detail::clearAgainstCandidates(world, context, cover, detail::fullCandidates(world, context, 0, CheckScope::kAll),
                                   {}, clear);
    for (int l = 0; l < kBatchLanes; ++l) {
      answers[l] = false;
      if (clear[l] != 0.0) continue;  // cleared: free to the exact check too
      ++exact_checks;
      answers[l] = robotInCollision(world, context, {.robot = 0, .q = qs[l]}, none);
    }
  }
};

// ---- benchmarks ----------------------------------------------------------------------------------

void BM_CollisionWorld(benchmark::State& state) {
  const CollisionWorld& world = benchWorld();
  CollisionContext context(world);
  const ObjectLayout none = ObjectLayout::empty(benchScene());
  const auto& qs = benchConfigurations();
  RobotState robot{.robot = 0};
  std::size_t i = 0;
  for (auto _ : state) {
    robot.q = qs[i];
    benchmark::DoNotOptimize(robotInCollision(world, context, robot, none));
    i = (i + 1) % qs.size();
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["narrowphase_per_check"] = static_cast<double>(context.counters().narrowphase_calls) /
                                            static_cast<double>(context.counters().configuration_checks);
}
BENCHMARK(BM_CollisionWorld)->Repetitions(5)->DisplayAggregatesOnly(true);

void BM_CollisionWorldNoCover(benchmark::State& state) {
  setCoverFastPath(false);
  BM_CollisionWorld(state);
  setCoverFastPath(true);
}
BENCHMARK(BM_CollisionWorldNoCover)->Repetitions(5)->DisplayAggregatesOnly(true);

void BM_CoverBatch(benchmark::State& state) {
  CoverChecker check;
  const auto& qs = benchConfigurations();
  static_assert(kConfigurations % kBatchLanes == 0);
  std::size_t i = 0;
  bool answers[kBatchLanes];
  for (auto _ : state) {
    check(&qs[i], answers);
    benchmark::DoNotOptimize(answers);
    i = (i + kBatchLanes) % qs.size();
  }
  state.SetItemsProcessed(state.iterations() * kBatchLanes);
  state.counters["exact_share"] = static_cast<double>(check.exact_checks) /
                                  static_cast<double>(state.iterations() * kBatchLanes);
}
BENCHMARK(BM_CoverBatch)->Repetitions(5)->DisplayAggregatesOnly(true);

template <class Checker>
void runBaseline(benchmark::State& state) {
  Checker check;
  const auto& qs = benchConfigurations();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(check(qs[i]));
    i = (i + 1) % qs.size();
  }
  state.SetItemsProcessed(state.iterations());
}

void BM_NaiveFcl(benchmark::State& state) { runBaseline<NaiveChecker>(state); }
BENCHMARK(BM_NaiveFcl)->Repetitions(5)->DisplayAggregatesOnly(true);

void BM_FclBroadphase(benchmark::State& state) { runBaseline<BroadphaseChecker>(state); }
BENCHMARK(BM_FclBroadphase)->Repetitions(5)->DisplayAggregatesOnly(true);

/// Keeps the median items/s of each benchmark for the closing summary.
class MedianReporter : public benchmark::ConsoleReporter {
 public:
  std::map<std::string, double> median_items_per_second;

  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Aggregate || run.aggregate_name != "median") continue;
      const auto it = run.counters.find("items_per_second");
      if (it != run.counters.end()) median_items_per_second[run.run_name.function_name] = it->second.value;
    }
    ConsoleReporter::ReportRuns(runs);
  }
};

/// All checkers must give the same answer on every configuration.
int disagreements() {
  CollisionContext context(benchWorld());
  const ObjectLayout none = ObjectLayout::empty(benchScene());
  NaiveChecker naive;
  BroadphaseChecker broadphase;
  CoverChecker cover;
  const auto& qs = benchConfigurations();
  int differ = 0;
  for (std::size_t i = 0; i < qs.size(); i += kBatchLanes) {
    bool batched[kBatchLanes];
    cover(&qs[i], batched);
    for (int l = 0; l < kBatchLanes; ++l) {
      const JointVector& q = qs[i + static_cast<std::size_t>(l)];
      const bool ours = robotInCollision(benchWorld(), context, {.robot = 0, .q = q}, none);
      if (ours != naive(q) || ours != broadphase(q) || ours != batched[l]) ++differ;
    }
  }
  return differ;
}

}  // namespace
}  // namespace dash

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  const int differ = dash::disagreements();
  std::printf("configurations: %zu (%.0f%% collision-free), boxes: %d, disagreements with the FCL baselines: %d\n",
              dash::benchConfigurations().size(), 100.0 * dash::kFreeShare, dash::kBoxes, differ);
  dash::MedianReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  const auto& m = reporter.median_items_per_second;
  const auto get = [&](const char* name) {
    const auto it = m.find(name);
    return it == m.end() ? 0.0 : it->second;
  };
  const double ours = get("BM_CollisionWorld");
  const double batch = get("BM_CoverBatch");
  std::printf("\nmedian configurations/s: vectorised cover batch %.0f, CollisionWorld %.0f (covers off %.0f), naive FCL "
              "loop %.0f, FCL broad phase %.0f\n",
              batch, ours, get("BM_CollisionWorldNoCover"), get("BM_NaiveFcl"), get("BM_FclBroadphase"));
  if (get("BM_NaiveFcl") > 0.0 && get("BM_FclBroadphase") > 0.0) {
    std::printf("vectorised cover batch: %.1fx the naive FCL loop, %.1fx the FCL broad phase\n",
                batch / get("BM_NaiveFcl"), batch / get("BM_FclBroadphase"));
  }
  std::printf("goal >= 5000000 configurations/s (vectorised): %s; >= 50x the FCL broad phase: %s\n",
              batch >= 5e6 ? "met" : "NOT met",
              get("BM_FclBroadphase") > 0.0 && batch >= 50.0 * get("BM_FclBroadphase") ? "met" : "NOT met");
  if (get("BM_NaiveFcl") > 0.0) std::printf("speed-up over the naive FCL loop: %.1fx\n", ours / get("BM_NaiveFcl"));
  if (get("BM_FclBroadphase") > 0.0) {
    std::printf("speed-up over the FCL broad phase: %.1fx\n", ours / get("BM_FclBroadphase"));
  }
  std::printf("goal >= 300000 configurations/s: %s\n", ours >= 300000.0 ? "met" : "NOT met");
  return differ == 0 ? 0 : 1;
}
