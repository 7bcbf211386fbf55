// The lazy roadmap's two ways to a configuration: the roadmap query, and global sampling with trees
// grown from both ends (RRT-Connect) for when the roadmap has no answer.
#include <gtest/gtest.h>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/motion/seeded_ompl.h"
#include "tests/conflict/two_arms.h"

namespace dash {
namespace {

struct OneArm : ::testing::Test, dash::testing::TwoArms {
  const OmplSeedScope ompl_seeds{1};
  MotionContext context_at_start() const { return {HeldObject{}, layout, {}}; }
  JointVector home() const { return scene.robots[0].home; }
  /// The home posture turned about the base: far from home in joint space, free of everything.
  JointVector turned() const {
    JointVector q = home();
    q[0] += q[0] > 0.0 ? -2.6 : 2.6;
    return q;
  }
  void expectValidPath(const std::vector<JointVector>& path, const JointVector& from, const JointVector& to) {
    ASSERT_GE(path.size(), 2u);
    EXPECT_TRUE(path.front().isApprox(from));
    EXPECT_TRUE(path.back().isApprox(to));
    for (std::size_t i = 1; i < path.size(); ++i) {
      EXPECT_FALSE(segmentInCollision(world, context, RobotState{0, path[i - 1], HeldObject{}}, path[i], layout))
          << "segment " << i;
      // Timed paths cannot spend no time on a move: no state repeats the one before.
      EXPECT_GE((path[i] - path[i - 1]).cwiseAbs().maxCoeff(), 1e-6) << "state " << i;
    }
  }
};

TEST_F(OneArm, TreesFindAPathTheRoadmapHasNoBudgetFor) {
  ASSERT_FALSE(robotInCollision(world, context, RobotState{0, turned(), HeldObject{}}, layout));
  RoadmapParams params;
  params.query_samples = 1;  // start and goal are more than one edge apart: the roadmap cannot answer
  LazyRoadmap roadmap(world, context, 0, params);
  EXPECT_FALSE(roadmap.query(home(), turned(), context_at_start(), Deadline()).has_value());
  const auto path = roadmap.queryTrees(home(), turned(), context_at_start(), Deadline());
  ASSERT_TRUE(path.has_value());
  expectValidPath(*path, home(), turned());
}

// keep_tree_paths: the path global sampling found joins the roadmap, so the next roadmap query
// between the same ends answers from it (no budget needed); without it the roadmap still cannot.
TEST_F(OneArm, ATreesPathJoinsTheRoadmap) {
  for (const bool keep : {true, false}) {
    RoadmapParams params;
    params.query_samples = 1;
    params.keep_tree_paths = keep;
    LazyRoadmap roadmap(world, context, 0, params);
    ASSERT_FALSE(roadmap.query(home(), turned(), context_at_start(), Deadline()).has_value());
    const std::size_t before = roadmap.vertexCount();
    ASSERT_TRUE(roadmap.queryTrees(home(), turned(), context_at_start(), Deadline()).has_value());
    const auto again = roadmap.query(home(), turned(), context_at_start(), Deadline());
    EXPECT_EQ(again.has_value(), keep) << "keep_tree_paths " << keep;
    if (keep) {
      EXPECT_GT(roadmap.vertexCount(), before);  // the tree path's inner states
      expectValidPath(*again, home(), turned());
    }
  }
}

TEST_F(OneArm, TreesAnswerAnInvalidEndAtOnce) {
  LazyRoadmap roadmap(world, context, 0);
  JointVector into_table = home();
  into_table[1] = 0.9;  // shoulder down past the horizontal: the arm goes through its own table
  into_table[2] = 1.2;
  ASSERT_TRUE(robotInCollision(world, context, RobotState{0, into_table, HeldObject{}}, layout));
  EXPECT_FALSE(roadmap.queryTrees(home(), into_table, context_at_start(), Deadline()).has_value());
}

TEST_F(OneArm, RoadmapQueryFindsAValidPath) {
  LazyRoadmap roadmap(world, context, 0);
  const auto path = roadmap.query(home(), turned(), context_at_start(), Deadline());
  ASSERT_TRUE(path.has_value());
  expectValidPath(*path, home(), turned());
}

TEST(RoadmapBudget, GrowthSlowsWhenDenseAndStopsAtTheMaximum) {
  const RoadmapParams params;  // the defaults
  EXPECT_EQ(querySampleBudget(params, 0), 5000u);
  EXPECT_EQ(querySampleBudget(params, 9999), 5000u);
  EXPECT_EQ(querySampleBudget(params, 10000), 1000u);
  EXPECT_EQ(querySampleBudget(params, 29999), 1000u);
  EXPECT_EQ(querySampleBudget(params, 30000), 0u);
  EXPECT_EQ(querySampleBudget(params, 486000), 0u);
  RoadmapParams small;
  small.query_samples = 10;  // a smaller query budget is never raised
  EXPECT_EQ(querySampleBudget(small, 20000), 10u);
}

TEST_F(OneArm, ARoadmapAtItsMaximumStopsGrowingAndAnswersFromWhatItHas) {
  RoadmapParams params;
  params.max_vertices = 10;  // reached by the first query, which grows the roadmap until it answers
  LazyRoadmap roadmap(world, context, 0, params);
  ASSERT_TRUE(roadmap.query(home(), turned(), context_at_start(), Deadline()).has_value());
  const std::size_t grown = roadmap.vertexCount();
  ASSERT_GE(grown, params.max_vertices);
  for (int i = 0; i < 5; ++i) {
    const auto path = roadmap.query(turned(), home(), context_at_start(), Deadline());
    ASSERT_TRUE(path.has_value()) << "query " << i;
    expectValidPath(*path, turned(), home());
  }
  // A query adds at most its two ends and draws no sample.
  EXPECT_LE(roadmap.vertexCount(), grown + 5 * 2);
}

}  // namespace
}  // namespace dash
