// The validator's report does not depend on its number of threads (issue 23: the planners feed its first
// problem back, so the plan would). A hand-made two-gantry plan with several contacts, cut into enough
// stretches that two threads share them, is validated with one thread and with more: every field of
// the report must be the same, in the same order.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <vector>

#include "certified_test_scenes.h"
#include "engine/plan/plan_validator.h"

namespace dash {
namespace {

/// Each thread gets 64 stretches (certified_geometry.cpp) or 256 samples (validation_geometry.cpp) at
/// least: a plan needs twice that many for two threads to share it.
constexpr std::size_t kStretchesForTwoThreads = 2 * 64;
constexpr std::size_t kSamplesForTwoThreads = 2 * 256;
/// Pieces each segment of the plan is cut into: enough stretches and samples for two threads.
constexpr int kPieces = 32;

/// Each segment of each trajectory cut into `pieces` equal ones: the same straight joint-space motion,
/// many more stretches between point times.
Plan densified(Plan plan, int pieces) {
  for (RobotTrajectory& traj : plan.robots) {
    std::vector<TrajectoryPoint> points{traj.points.front()};
    for (std::size_t k = 1; k < traj.points.size(); ++k) {
      const TrajectoryPoint& a = traj.points[k - 1];
      const TrajectoryPoint& b = traj.points[k];
      for (int j = 1; j < pieces; ++j) {
        const double s = static_cast<double>(j) / pieces;
        points.push_back({a.t + s * (b.t - a.t), JointVector(a.q + s * (b.q - a.q))});
      }
      points.push_back(b);
    }
    traj.points = std::move(points);
  }
  return plan;
}

std::size_t distinctTimes(const Plan& plan) {
  std::vector<double> times;
  for (const RobotTrajectory& traj : plan.robots)
    for (const TrajectoryPoint& p : traj.points) times.push_back(p.t);
  std::sort(times.begin(), times.end());
  return static_cast<std::size_t>(std::unique(times.begin(), times.end()) - times.begin());
}

/// twoGantriesScene: gantry_0 picks cube_0 up and puts it back (events at 4 and 6) while gantry_1 dips
/// its tool 2 mm into cube_1 (never grasped: a contact) across both events; then gantry_0 drives into
/// gantry_1 parked beside it, passes it to dip into cube_1 as well, and comes back past it.
Plan busyPlan(const Scene& scene) {
  using test::joints;
  using test::point;
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const auto& names = scene.robots[0].model->joint_names;
  RobotTrajectory a = test::liftAndPutBackCube0(scene, plan);
  a.points.push_back(point(8.0, joints({0.3, 0.2, 0.0})));
  a.points.push_back(point(10.0, joints({0.65, 0.2, 0.0})));  // into gantry_1 parked at world x 0.7
  a.points.push_back(point(11.0, joints({0.65, 0.2, 0.0})));
  a.points.push_back(point(13.0, joints({0.9, 0.2, 0.0})));   // through it, over cube_1
  a.points.push_back(point(15.0, joints({0.9, 0.2, 0.262})));
  a.points.push_back(point(17.0, joints({0.9, 0.2, 0.0})));
  a.points.push_back(point(20.0, joints({0.1, 0.1, 0.0})));   // back through it
  RobotTrajectory b{"gantry_1", names, {point(0.0, scene.robots[1].home)}};
  b.points.push_back(point(1.0, joints({0.3, 0.2, 0.0})));    // over cube_1 (world x 0.9)
  b.points.push_back(point(3.0, joints({0.3, 0.2, 0.262})));
  b.points.push_back(point(6.5, joints({0.3, 0.2, 0.262})));
  b.points.push_back(point(8.5, joints({0.3, 0.2, 0.0})));
  b.points.push_back(point(9.5, joints({0.1, 0.2, 0.0})));
  b.points.push_back(point(20.0, joints({0.1, 0.2, 0.0})));
  plan.robots.push_back(std::move(a));
  plan.robots.push_back(std::move(b));
  plan.makespan = 20.0;
  return plan;
}

void expectSameReport(const ValidationReport& one, const ValidationReport& many, int threads) {
  SCOPED_TRACE(testing::Message() << threads << " threads");
  EXPECT_EQ(many.samples, one.samples);
  ASSERT_EQ(many.problems.size(), one.problems.size()) << many.summary() << "vs one thread:\n" << one.summary();
  for (std::size_t i = 0; i < one.problems.size(); ++i) {
    const ValidationProblem& p = one.problems[i];
    const ValidationProblem& q = many.problems[i];
    SCOPED_TRACE(testing::Message() << "problem " << i << ": " << p.message);
    EXPECT_EQ(q.kind, p.kind);
    EXPECT_EQ(q.t, p.t);
    EXPECT_EQ(q.t_end, p.t_end);
    EXPECT_EQ(q.robot, p.robot);
    EXPECT_EQ(q.object, p.object);
    EXPECT_EQ(q.other, p.other);
    EXPECT_EQ(q.message, p.message);
    EXPECT_EQ(q.distance, p.distance);
    EXPECT_EQ(q.t_closest, p.t_closest);
  }
  auto expectSamePair = [](const PairClearance& q, const PairClearance& p) {
    EXPECT_EQ(q.a, p.a);
    EXPECT_EQ(q.b, p.b);
    EXPECT_EQ(q.distance, p.distance);
    EXPECT_EQ(q.t, p.t) << p.a << " / " << p.b;
    EXPECT_EQ(q.contact_allowed, p.contact_allowed);
  };
  expectSamePair(many.closest, one.closest);
  ASSERT_EQ(many.pairs.size(), one.pairs.size());
  for (std::size_t i = 0; i < one.pairs.size(); ++i) expectSamePair(many.pairs[i], one.pairs[i]);
}

TEST(ValidationThreads, CertifiedReportIsTheSameWithOneThreadOrMore) {
  const Scene scene = test::twoGantriesScene();
  const Plan plan = densified(busyPlan(scene), kPieces);
  ASSERT_GE(distinctTimes(plan), kStretchesForTwoThreads);
  const ValidationReport one = validatePlan(scene, plan, {.threads = 1});
  // Several problems of two kinds, so that their order matters.
  ASSERT_GE(one.problems.size(), 4u) << one.summary();
  EXPECT_GE(one.count(ProblemKind::kRobotRobotCollision), 2) << one.summary();
  EXPECT_GE(one.count(ProblemKind::kRobotObjectCollision), 2) << one.summary();
  EXPECT_GT(one.samples, 0u);
  EXPECT_FALSE(one.pairs.empty());
  for (const int threads : {2, 3}) expectSameReport(one, validatePlan(scene, plan, {.threads = threads}), threads);
}

TEST(ValidationThreads, SampledReportIsTheSameWithOneThreadOrMore) {
  const Scene scene = test::twoGantriesScene();
  const Plan plan = densified(busyPlan(scene), kPieces);
  ValidationOptions options;
  options.geometry = ValidationOptions::GeometryCheck::kSampled;
  options.threads = 1;
  const ValidationReport one = validatePlan(scene, plan, options);
  ASSERT_GE(one.samples, kSamplesForTwoThreads);  // the sampled check's samples are its instants
  ASSERT_GE(one.problems.size(), 4u) << one.summary();
  for (const int threads : {2, 3}) {
    options.threads = threads;
    expectSameReport(one, validatePlan(scene, plan, options), threads);
  }
}

// A planner passes its deadline as `stop`: polled before each stretch, on every worker; once it says
// stop, the report is `stopped` and not valid (it covers part of the plan, so it reports no problem),
// whatever the number of threads. A stop that never fires changes nothing.
TEST(ValidationThreads, AStopPolledBetweenStretchesEndsTheCertifiedCheckUncertified) {
  const Scene scene = test::twoGantriesScene();
  const Plan plan = densified(busyPlan(scene), kPieces);
  const ValidationReport whole = validatePlan(scene, plan, {.threads = 1});
  for (const int threads : {1, 2}) {
    SCOPED_TRACE(testing::Message() << threads << " threads");
    std::atomic<int> polls{0};
    const ValidationReport cut =
        validatePlan(scene, plan, {.threads = threads, .stop = [&polls] { return ++polls > 10; }});
    EXPECT_TRUE(cut.stopped);
    EXPECT_FALSE(cut.valid());
    EXPECT_TRUE(cut.problems.empty()) << cut.summary();
    EXPECT_LT(polls.load(), 40) << "the check went on after the stop";
    const ValidationReport never = validatePlan(scene, plan, {.threads = threads, .stop = [] { return false; }});
    EXPECT_FALSE(never.stopped);
    expectSameReport(whole, never, threads);
  }
}

}  // namespace
}  // namespace dash
