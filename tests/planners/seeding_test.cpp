// A seed gives the same plan whatever ran before it in the process: OMPL's randomness comes from the
// run's seed (engine/motion/seeded_ompl.h), not from OMPL's process-wide seed sequence.
#include <gtest/gtest.h>

#include "engine/motion/seeded_ompl.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash {
namespace {

std::string planText(const std::string& planner, std::uint64_t seed) {
  const Scene scene =
      generateScenario("shelf-wall", {{"robots", "2"}, {"objects", "2"}}, 1, RobotLibrary::loadDefault());
  PlannerSettings settings;
  settings.seed = seed;
  settings.time_limit = 120;
  const PlanResult result = makePlanner(planner)->solve(scene, settings, Deadline(settings.time_limit), nullptr);
  EXPECT_EQ(result.outcome, PlanOutcome::kSolved) << planner << ": " << result.message;
  return result.plan ? planToJson(*result.plan) : std::string();
}

TEST(Seeding, SameSeedSamePlanAfterOtherRunsInTheProcess) {
  const std::string first = planText("lazy-dash", 3);
  planText("lazy-dash", 4);  // another run in between draws OMPL samples of its own
  EXPECT_EQ(planText("lazy-dash", 3), first);
}

TEST(Seeding, ScopesGiveTheirOwnSequences) {
  std::uint_fast32_t a1, a2, b1;
  {
    const OmplSeedScope scope(7);
    a1 = nextOmplSeed();
    a2 = nextOmplSeed();
    {
      const OmplSeedScope inner(8);
      b1 = nextOmplSeed();
    }
    EXPECT_NE(a1, a2);
  }
  const OmplSeedScope again(7);
  EXPECT_EQ(nextOmplSeed(), a1);  // a scope's sequence does not depend on what was drawn before
  EXPECT_EQ(nextOmplSeed(), a2);
  EXPECT_NE(b1, a1);
}

}  // namespace
}  // namespace dash
