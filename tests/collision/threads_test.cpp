// One world, one context per thread: concurrent queries give the single-threaded answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>
#include <vector>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/core/rng.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

std::vector<JointVector> randomConfigurations(std::uint64_t seed, int count) {
  Rng rng(seed);
  std::vector<JointVector> out;
  for (int k = 0; k < count; ++k) {
    JointVector q(6);
    for (int i = 0; i < 6; ++i) q[i] = rng.uniform(-M_PI, M_PI);
    out.push_back(q);
  }
  return out;
}

/// Point and segment answers for every configuration (segment k goes from configuration k to k+1).
std::vector<int> answers(const CollisionWorld& world, CollisionContext& context, const std::vector<JointVector>& qs,
                         const ObjectLayout& layout) {
  std::vector<int> out;
  for (std::size_t k = 0; k < qs.size(); ++k) {
    CollisionReport report;
    const RobotState state{.robot = 0, .q = qs[k], .held = {.object = 0, .X_TO = Pose::Identity()}};
    const bool hit = robotInCollision(world, context, state, layout, &report);
    out.push_back(hit ? 1 + report.b.index + 100 * static_cast<int>(report.b.kind) : 0);
    if (k + 1 < qs.size()) out.push_back(segmentInCollision(world, context, state, qs[k + 1], layout) ? 1 : 0);
  }
  return out;
}

TEST(Threads, TwoContextsQueryOneWorldAtOnce) {
  Scene scene = test::exampleScene();
  test::addCube(scene, "second", 0.04, makePose(Vec3(0.4, 0.3, 0.02)));
  test::addObstacle(scene, "post", Vec3(0.1, 0.1, 0.8), makePose(Vec3(0.3, -0.4, 0.4)));
  const CollisionWorld world(scene);
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  const auto qs_a = randomConfigurations(1, 300);
  const auto qs_b = randomConfigurations(2, 300);
  CollisionContext reference_context(world);
  const auto expected_a = answers(world, reference_context, qs_a, layout);
  const auto expected_b = answers(world, reference_context, qs_b, layout);
  // Both outcomes occur, so the comparison means something.
  EXPECT_GT(std::count(expected_a.begin(), expected_a.end(), 0), 10);
  EXPECT_GT(std::count_if(expected_a.begin(), expected_a.end(), [](int x) { return x != 0; }), 10);

  std::vector<int> got_a;
  std::vector<int> got_b;
  CollisionContext context_a(world);
  CollisionContext context_b(world);
  for (int round = 0; round < 3; ++round) {
    std::thread ta([&] { got_a = answers(world, context_a, qs_a, layout); });
    std::thread tb([&] { got_b = answers(world, context_b, qs_b, layout); });
    ta.join();
    tb.join();
    EXPECT_EQ(got_a, expected_a);
    EXPECT_EQ(got_b, expected_b);
  }
  EXPECT_GE(context_a.counters().configuration_checks, 3u * 300u);
}

}  // namespace
}  // namespace dash
