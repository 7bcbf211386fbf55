// Lazy-DaSH never ends "infeasible" on a problem it cannot prove infeasible: when nothing is left to
// try it restarts (every task constraint lifted, fresh samples, larger roadmap budgets) until its
// deadline. Only an object that H_T itself gives no route (its goal out of every robot's reach) ends
// the run early, and the message names it. With restarts off (the paper) the run ends "infeasible".
#include <gtest/gtest.h>

#include "engine/events/memory_sink.h"
#include "engine/planners/lazy_dash.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash {
namespace {

constexpr double kDeadlineSeconds = 4.0;

// A task layer allowed a single query-and-detection iteration per plan: a scene whose first task plan
// has a task conflict exhausts it at once, every attempt.
LazyDashParams oneTaskIteration() {
  LazyDashParams p;
  p.task.max_iterations = 1;
  return p;
}

PlanResult solve(const Scene& scene, LazyDashParams params, log::MemorySink& sink) {
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = kDeadlineSeconds;
  return LazyDash(std::move(params)).solve(scene, settings, Deadline(kDeadlineSeconds), &sink);
}

// Its first task plan has a task conflict (Algorithm 2): one iteration per attempt never suffices.
Scene conflictingScene() {
  return generateScenario("shelf-wall", {{"robots", "2"}, {"objects", "4"}}, 1, RobotLibrary::loadDefault());
}

TEST(LazyDashRestart, AnExhaustedAttemptRestartsUntilTheDeadline) {
  const Scene scene = conflictingScene();
  log::MemorySink sink;
  const PlanResult r = solve(scene, oneTaskIteration(), sink);
  EXPECT_EQ(r.outcome, PlanOutcome::kTimeout) << r.message;
  EXPECT_GT(sink.counter("restarts"), 1);
  EXPECT_NE(r.message.find("restarts; the last after: task layer: infeasible (task layer iteration limit"),
            std::string::npos)
      << r.message;
  EXPECT_GE(r.stats.wall_seconds, kDeadlineSeconds * 0.99);
  // Every attempt makes one task plan (one task query) and restarts on its iteration limit: none
  // reaches the 200 task plans an attempt may try, a count that starts again at each restart like every
  // other allowance of an attempt. (Counted over the whole run, it restarted every 201st time with no
  // task query at all.)
  int task_queries = 0;
  for (const log::Event& e : sink.events()) {
    const auto* p = std::get_if<log::PhaseEvent>(&e.payload);
    task_queries += p != nullptr && p->phase == log::Phase::TaskQuery && p->boundary == log::PhaseBoundary::Start;
  }
  EXPECT_LE(sink.counter("restarts"), task_queries);
}

TEST(LazyDashRestart, WithRestartsOffTheSameAttemptEndsInfeasible) {
  const Scene scene = conflictingScene();
  LazyDashParams params = oneTaskIteration();
  params.restart_when_exhausted = false;
  log::MemorySink sink;
  const PlanResult r = solve(scene, params, sink);
  EXPECT_EQ(r.outcome, PlanOutcome::kInfeasible) << r.message;
  EXPECT_NE(r.message.find("iteration limit"), std::string::npos) << r.message;
  EXPECT_EQ(sink.counter("restarts"), 0);
}

TEST(LazyDashRestart, AGoalOutOfEveryRobotsReachEndsTheRunAtOnceNamingTheObject) {
  Scene scene = generateScenario("sorting", {{"robots", "2"}, {"objects", "2"}}, 1, RobotLibrary::loadDefault());
  ASSERT_TRUE(scene.objects[0].X_WO_goal.has_value());
  scene.objects[0].X_WO_goal->translation() += Vec3(20.0, 0.0, 0.0);
  log::MemorySink sink;
  const PlanResult r = solve(scene, LazyDashParams{}, sink);
  EXPECT_EQ(r.outcome, PlanOutcome::kInfeasible) << r.message;
  EXPECT_NE(r.message.find(scene.objects[0].id + " has no route to its goal"), std::string::npos) << r.message;
  EXPECT_EQ(sink.counter("restarts"), 0);
  EXPECT_LT(r.stats.wall_seconds, kDeadlineSeconds);
}

}  // namespace
}  // namespace dash
