// OMPL's Lazy-PRM with validity split into static (removed when invalid) and context (skipped while the
// context lasts, never removed), on the unit square with a wall across it.
#include <gtest/gtest.h>

#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include <ompl/base/PlannerData.h>

#include "engine/motion/context_lazy_prm.h"
#include "engine/motion/ompl_validity.h"
#include "engine/motion/seeded_ompl.h"

namespace dash {
namespace {

namespace ob = ompl::base;

double x(const ob::State* s) { return s->as<ob::RealVectorStateSpace::StateType>()->values[0]; }
double y(const ob::State* s) { return s->as<ob::RealVectorStateSpace::StateType>()->values[1]; }

/// A wall 0.4 <= x <= 0.6, open above y = `gap` (1: closed, -1: no wall). A segment is checked at 100 points.
struct Wall {
  double gap = 1.0;
  bool state(double px, double py) const { return px < 0.4 || px > 0.6 || py > gap; }
  bool state(const ob::State* s) const { return state(x(s), y(s)); }
  bool motion(const ob::State* a, const ob::State* b) const {
    for (int i = 0; i <= 100; ++i) {
      const double t = i / 100.0;
      if (!state(x(a) + t * (x(b) - x(a)), y(a) + t * (y(b) - y(a)))) return false;
    }
    return true;
  }
};

struct ContextLazyPRMTest : ::testing::Test {
  const OmplSeedScope seeds{7};
  Wall static_wall{-1.0};  // no static obstacle unless a test sets one
  int static_state_checks = 0;
  std::vector<std::pair<double, double>> rejected;  ///< states the static check rejected
  std::shared_ptr<ob::SpaceInformation> si;
  std::shared_ptr<ContextLazyPRM> prm;
  ob::State* start = nullptr;
  ob::State* goal = nullptr;

  void SetUp() override {
    auto space = std::make_shared<ob::RealVectorStateSpace>(2);
    space->setBounds(0.0, 1.0);
    seedStateSamplers(*space);
    si = std::make_shared<ob::SpaceInformation>(space);
    installValidity(
        si,
        [this](const ob::State* s) {
          ++static_state_checks;
          if (static_wall.state(s)) return true;
          rejected.emplace_back(x(s), y(s));
          return false;
        },
        [this](const ob::State* a, const ob::State* b) { return static_wall.motion(a, b); });
    si->setup();
    prm = std::make_shared<ContextLazyPRM>(si);
    prm->setRange(0.3);
    prm->setMaxNearestNeighbors(10);
    prm->setup();
    start = si->allocState();
    goal = si->allocState();
    start->as<ob::RealVectorStateSpace::StateType>()->values[0] = 0.1;
    start->as<ob::RealVectorStateSpace::StateType>()->values[1] = 0.5;
    goal->as<ob::RealVectorStateSpace::StateType>()->values[0] = 0.9;
    goal->as<ob::RealVectorStateSpace::StateType>()->values[1] = 0.5;
  }
  void TearDown() override {
    si->freeState(start);
    si->freeState(goal);
  }
  std::optional<std::vector<const ob::State*>> solve(const Wall& context, std::size_t samples) {
    return prm->solveInContext(
        start, goal, samples, [] { return false; }, [&](const ob::State* s) { return context.state(s); },
        [&](const ob::State* a, const ob::State* b) { return context.motion(a, b); });
  }
  void expectPathValidIn(const std::vector<const ob::State*>& path, const Wall& wall) {
    ASSERT_GE(path.size(), 2u);
    EXPECT_DOUBLE_EQ(x(path.front()), 0.1);
    EXPECT_DOUBLE_EQ(x(path.back()), 0.9);
    for (std::size_t i = 1; i < path.size(); ++i) EXPECT_TRUE(wall.motion(path[i - 1], path[i])) << "edge " << i;
  }
};

TEST_F(ContextLazyPRMTest, WhatTheContextRejectsIsSkippedNotRemoved) {
  const Wall closed{1.0};
  EXPECT_FALSE(solve(closed, 300).has_value());
  // Ends and samples all stay: the wall of that context removed nothing.
  EXPECT_EQ(prm->milestoneCount(), 302u);
  const std::size_t edges = prm->edgeCount();
  prm->forgetContext();
  const Wall none{-1.0};
  const auto path = solve(none, 0);  // no new sample: the roadmap as it was answers
  ASSERT_TRUE(path.has_value());
  expectPathValidIn(*path, none);
  EXPECT_EQ(prm->milestoneCount(), 302u);  // the same ends are the same vertices
  EXPECT_GE(prm->edgeCount(), edges);
}

TEST_F(ContextLazyPRMTest, AContextPathAvoidsWhatThatContextRejects) {
  const Wall open_above{0.8};
  const auto path = solve(open_above, 2000);
  ASSERT_TRUE(path.has_value());
  expectPathValidIn(*path, open_above);
  for (const ob::State* s : *path) EXPECT_TRUE(open_above.state(s));
}

TEST_F(ContextLazyPRMTest, WhatIsStaticallyInvalidIsRemovedForGoodAndStaticVerdictsOutliveTheContext) {
  static_wall.gap = 0.8;
  const auto path = solve(Wall{-1.0}, 2000);
  ASSERT_TRUE(path.has_value());
  expectPathValidIn(*path, static_wall);
  // Vertices in the wall lay on searched paths, and none of them is left in the roadmap.
  ASSERT_FALSE(rejected.empty());
  ob::PlannerData data(si);
  prm->getPlannerData(data);
  for (unsigned int i = 0; i < data.numVertices(); ++i) {
    const ob::State* s = data.getVertex(i).getState();
    for (const auto& [rx, ry] : rejected) EXPECT_FALSE(x(s) == rx && y(s) == ry) << "vertex " << i;
  }
  // A new context checks the same path again in its context, never statically.
  prm->forgetContext();
  const int static_checks = static_state_checks;
  int context_checks = 0;
  const auto again = prm->solveInContext(
      start, goal, 0, [] { return false; },
      [&](const ob::State*) {
        ++context_checks;
        return true;
      },
      [](const ob::State*, const ob::State*) { return true; });
  ASSERT_TRUE(again.has_value());
  expectPathValidIn(*again, static_wall);
  EXPECT_GT(context_checks, 0);
  EXPECT_EQ(static_state_checks, static_checks);  // the same path: its vertices keep their static verdicts
}

TEST(ContextLazyPRMBatch, SamplesPerSearchGrowWithTheRoadmap) {
  EXPECT_EQ(ContextLazyPRM::sampleBatch(0), 1u);
  EXPECT_EQ(ContextLazyPRM::sampleBatch(100), 1u);
  EXPECT_EQ(ContextLazyPRM::sampleBatch(6400), 100u);
}

}  // namespace
}  // namespace dash
