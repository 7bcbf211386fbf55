// The same seed gives the same plan with the covers' fast reject on and off (issue 38): the fast path
// only skips exact checks whose answer it knows (cover_check.h), so Lazy-DaSH must take the same
// decisions, constraints and plan on a small scene of every family; and with two validator threads
// (the fast path's scratch is per thread), which are also two lanes of conflict resolution's checks
// (engine/conflict/check_pool.h), the same again. Each run is forked from one state
// (OMPL's process-wide generator, see tests/planners/validation_threads_plan_test.cpp) and the switch
// set in the child.
#include <gtest/gtest.h>
#include <ompl/util/RandomNumbers.h>

#include <string>
#include <variant>
#include <vector>

#include "engine/collision/cover_check.h"
#include "engine/core/forked_run.h"
#include "engine/events/memory_sink.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "tests/common/robot_library.h"

namespace dash {
namespace {

constexpr double kTimeLimit = 60.0;

/// Outcome, every constraint's cause and the plan, one text.
std::string solveToText(const Scene& scene, bool fast_path, int validation_threads) {
  setCoverFastPath(fast_path);
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = kTimeLimit;
  settings.params["validation_threads"] = std::to_string(validation_threads);
  log::MemorySink sink;
  const PlanResult result = makePlanner("lazy-dash")->solve(scene, settings, Deadline(settings.time_limit), &sink);
  std::string out = "outcome " + std::to_string(static_cast<int>(result.outcome)) + "\n";
  for (const log::Event& e : sink.events())
    if (const auto* c = std::get_if<log::ConstraintEvent>(&e.payload)) out += "constraint " + c->conflict + "\n";
  if (result.plan) out += planToJson(*result.plan);
  return out;
}

std::string solveInChild(const Scene& scene, bool fast_path, int validation_threads) {
  const ForkedRun run = runForked([&] { return solveToText(scene, fast_path, validation_threads); });
  EXPECT_TRUE(run.finished) << "the child run did not finish";
  return run.output;
}

void expectSamePlanWithAndWithoutTheFastPath(const std::string& family,
                                             const std::vector<std::pair<std::string, std::string>>& params) {
  const Scene scene = generateScenario(family, params, 1, test::library());
  const ompl::RNG started;  // OMPL's generator starts here, once: both children inherit its state
  const std::string fast = solveInChild(scene, true, 1);
  const std::string exact = solveInChild(scene, false, 1);
  const std::string fast_two_threads = solveInChild(scene, true, 2);
  EXPECT_EQ(fast.rfind("outcome 0\n", 0), 0u) << family << ": not solved\n" << fast.substr(0, 400);
  EXPECT_GT(fast.size(), 1000u) << family << ": no plan";
  EXPECT_TRUE(fast == exact) << family << ": the runs differ\nfast:  " << fast.substr(0, 600)
                             << "\nexact: " << exact.substr(0, 600);
  EXPECT_TRUE(fast_two_threads == fast) << family << ": two validator threads change the run with the fast path";
}

TEST(CoverPlans, SortingGivesTheSamePlanWithTheFastPathOnOrOffAndOneOrTwoValidatorThreads) {
  expectSamePlanWithAndWithoutTheFastPath("sorting", {{"robots", "2"}, {"objects", "4"}});
}

TEST(CoverPlans, WallGivesTheSamePlanWithTheFastPathOnOrOffAndOneOrTwoValidatorThreads) {
  expectSamePlanWithAndWithoutTheFastPath("wall", {{"robots", "4"}, {"objects", "4"}});
}

TEST(CoverPlans, ShelfWallGivesTheSamePlanWithTheFastPathOnOrOffAndOneOrTwoValidatorThreads) {
  expectSamePlanWithAndWithoutTheFastPath("shelf-wall", {{"robots", "2"}, {"objects", "4"}});
}

TEST(CoverPlans, StockingGivesTheSamePlanWithTheFastPathOnOrOffAndOneOrTwoValidatorThreads) {
  expectSamePlanWithAndWithoutTheFastPath("stocking", {{"layers", "2"}, {"objects", "4"}});
}

TEST(CoverPlans, LabGivesTheSamePlanWithTheFastPathOnOrOffAndOneOrTwoValidatorThreads) {
  expectSamePlanWithAndWithoutTheFastPath("lab", {{"containers", "2"}});
}

}  // namespace
}  // namespace dash
