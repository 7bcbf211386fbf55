// ARC's subproblem: two UR5e arms whose straight, synchronised motions collide are replanned together
// in their composite space. Every segment of the answer is checked again here, independently.
#include <gtest/gtest.h>

#include <random>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/conflict/composite_planner.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash {
namespace {

JointVector randomConfig(const RobotModel& model, std::mt19937& rng) {
  JointVector q(model.dof());
  for (int i = 0; i < model.dof(); ++i) {
    const double lo = std::max(model.limits.position_min[i], -3.0);
    const double hi = std::min(model.limits.position_max[i], 3.0);
    q[i] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return q;
}

struct TwoArms {
  Scene scene = generateScenario("sorting", {{"robots", "2"}, {"objects", "2"}}, 1, RobotLibrary::loadDefault());
  CollisionWorld world{scene};
  CollisionContext context{world};
  ObjectLayout layout = ObjectLayout::atStart(scene);

  bool valid(const JointVector& a, const JointVector& b) {
    const RobotState states[2] = {{0, a, {}}, {1, b, {}}};
    return !robotsInCollision(world, context, states, layout);
  }
  bool segmentFree(const std::vector<JointVector>& from, const std::vector<JointVector>& to) {
    const RobotMotion motions[2] = {{{0, from[0], {}}, to[0]}, {{1, from[1], {}}, to[1]}};
    return !motionsInCollision(world, context, motions, layout);
  }

  /// Valid start and goal pairs whose straight composite motion collides (the arms cross).
  CompositeProblem crossingProblem(std::uint32_t seed) {
    std::mt19937 rng(seed);
    for (int attempt = 0; attempt < 20000; ++attempt) {
      const JointVector a0 = randomConfig(*scene.robots[0].model, rng), a1 = randomConfig(*scene.robots[0].model, rng);
      const JointVector b0 = randomConfig(*scene.robots[1].model, rng), b1 = randomConfig(*scene.robots[1].model, rng);
      if (!valid(a0, b0) || !valid(a1, b1)) continue;
      if (segmentFree({a0, b0}, {a1, b1})) continue;
      // Each arm alone can go straight: only their interaction is in the way.
      if (segmentInCollision(world, context, {0, a0, {}}, a1, layout) ||
          segmentInCollision(world, context, {1, b0, {}}, b1, layout))
        continue;
      CompositeProblem p;
      p.robots = {0, 1};
      p.start = {a0, b0};
      p.goal = {a1, b1};
      p.held = {HeldObject{}, HeldObject{}};
      p.layout = layout;
      return p;
    }
    ADD_FAILURE() << "no crossing problem found";
    return {};
  }
};

TEST(CompositePlanner, ArmsThatCrossAreReplannedTogether) {
  const OmplSeedScope ompl_seeds(7);
  TwoArms arms;
  int solved = 0;
  for (std::uint32_t seed = 1; seed <= 3; ++seed) {
    const CompositeProblem problem = arms.crossingProblem(seed);
    ASSERT_EQ(problem.robots.size(), 2u);
    CompositeParams params;
    params.seconds = 10.0;
    const auto path = planComposite(arms.world, arms.context, problem, params, Deadline(30));
    if (!path) continue;
    ++solved;
    ASSERT_GE(path->size(), 3u) << "the straight motion collides, so the answer must detour";
    EXPECT_EQ(path->front()[0], problem.start[0]);
    EXPECT_EQ(path->front()[1], problem.start[1]);
    EXPECT_EQ(path->back()[0], problem.goal[0]);
    EXPECT_EQ(path->back()[1], problem.goal[1]);
    for (std::size_t w = 1; w < path->size(); ++w)
      EXPECT_TRUE(arms.segmentFree((*path)[w - 1], (*path)[w])) << "segment " << w << " of problem " << seed;
  }
  EXPECT_GE(solved, 2);
}

TEST(CompositePlanner, ARobotStandingInTheWayIsRespected) {
  const OmplSeedScope ompl_seeds(7);
  TwoArms arms;
  CompositeProblem problem = arms.crossingProblem(1);
  ASSERT_EQ(problem.robots.size(), 2u);
  // Robot 1 stands still at its start: robot 0 alone must get round it.
  CompositeProblem alone;
  alone.robots = {0};
  alone.start = {problem.start[0]};
  alone.goal = {problem.goal[0]};
  alone.held = {HeldObject{}};
  alone.layout = problem.layout;
  alone.parked = {RobotState{1, problem.start[1], {}}};
  CompositeParams params;
  params.seconds = 10.0;
  const auto path = planComposite(arms.world, arms.context, alone, params, Deadline(30));
  if (!path) GTEST_SKIP() << "no path round the standing arm in this configuration";
  for (std::size_t w = 1; w < path->size(); ++w) {
    const RobotMotion motions[2] = {{{0, (*path)[w - 1][0], {}}, (*path)[w][0]},
                                    {{1, problem.start[1], {}}, problem.start[1]}};
    EXPECT_FALSE(motionsInCollision(arms.world, arms.context, motions, arms.layout)) << "segment " << w;
  }
}

TEST(CompositePlanner, InvalidEndsAreRefused) {
  TwoArms arms;
  CompositeProblem problem = arms.crossingProblem(2);
  ASSERT_EQ(problem.robots.size(), 2u);
  problem.goal[1] = problem.goal[0];  // robot 1 at robot 0's joint values: fine alone...
  problem.parked = {};
  // ...but put robot 0's goal inside the table: refused at once.
  problem.goal[0][1] = 1.2;
  problem.goal[0][2] = 0.0;
  const RobotState st{0, problem.goal[0], {}};
  if (!robotInCollision(arms.world, arms.context, st, arms.layout)) GTEST_SKIP() << "goal happens to be free";
  EXPECT_FALSE(planComposite(arms.world, arms.context, problem, {}, Deadline(5)).has_value());
}

}  // namespace
}  // namespace dash
