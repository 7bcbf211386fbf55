// Lab as the paper describes it ("Lab"), on real plans of both planners, validated: lids rest only in
// the sanitisation zone (or on their own container), the zone has room for fewer lids than there are
// containers, and with both gantries lifting lids more lids are out at once than one gantry can hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "engine/plan/plan_validator.h"
#include "engine/plan/validation_timeline.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scene/support.h"

namespace dash {
namespace {

struct LidUse {
  int resting_outside_zone = 0;  ///< epochs x lids resting away from their start but not in the zone
  int most_away = 0;             ///< most lids away from their container (resting elsewhere or held) at once
};

/// Replays the plan's events (the validator's own timeline) and looks at every lid in every epoch.
LidUse lidUse(const Scene& scene, const Plan& plan) {
  int zone = -1;
  for (int s = 0; s < static_cast<int>(scene.surfaces.size()); ++s)
    if (scene.surfaces[s].id == "sanitisation_zone") zone = s;
  EXPECT_GE(zone, 0);
  const validation::PlanMotion motion(scene, plan);
  std::vector<ValidationProblem> problems;
  const validation::Timeline timeline = validation::replayEvents(plan, motion, {}, problems);
  EXPECT_TRUE(problems.empty());
  LidUse use;
  for (const validation::Epoch& epoch : timeline.epochs) {
    int away = 0;
    for (int j = 0; j < static_cast<int>(scene.objects.size()); ++j) {
      const SceneObject& object = scene.objects[static_cast<std::size_t>(j)];
      if (object.fixed) continue;
      const validation::ObjectState& state = epoch.objects[static_cast<std::size_t>(j)];
      const bool at_start = !state.held() && translationDistance(state.X_WO, object.X_WO_start) < 1e-3;
      if (at_start) continue;
      ++away;
      if (state.held()) continue;
      const Support support = findSupport(scene, j, state.X_WO, epoch.layout);
      if (support.kind != Support::Kind::kSurface || support.index != zone) ++use.resting_outside_zone;
    }
    use.most_away = std::max(use.most_away, away);
  }
  return use;
}

LidUse planAndCheck(const std::string& planner, int containers, std::uint64_t seed) {
  const Scene scene =
      generateScenario("lab", {{"containers", std::to_string(containers)}}, seed, RobotLibrary::loadDefault());
  EXPECT_LT(labZoneLids(containers), containers);
  PlannerSettings settings;
  settings.seed = seed;
  settings.time_limit = 120;
  const PlanResult r = makePlanner(planner)->solve(scene, settings, Deadline(settings.time_limit), nullptr);
  EXPECT_EQ(r.outcome, PlanOutcome::kSolved) << planner << ": " << r.message;
  if (!r.plan) return {};
  const ValidationReport report = validatePlan(scene, *r.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  return lidUse(scene, *r.plan);
}

TEST(LabLids, LazyDashRestsLidsOnlyInTheZone) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const LidUse use = planAndCheck("lazy-dash", 4, seed);
    EXPECT_EQ(use.resting_outside_zone, 0) << "seed " << seed;
    EXPECT_GE(use.most_away, 1) << "seed " << seed;
  }
}

TEST(LabLids, DashRestsLidsOnlyInTheZone) {
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const LidUse use = planAndCheck("dash", 4, seed);
    EXPECT_EQ(use.resting_outside_zone, 0) << "seed " << seed;
    EXPECT_GE(use.most_away, 1) << "seed " << seed;
  }
}

// One gantry holds one lid: a plan with two or more lids away at once has both gantries working,
// their lids in the zone side by side.
TEST(LabLids, MoreLidsAreOutAtOnceThanOneGantryCanHold) {
  int most = 0;
  for (const std::string planner : {"lazy-dash", "dash"}) {
    const LidUse use = planAndCheck(planner, 8, 1);
    EXPECT_EQ(use.resting_outside_zone, 0) << planner;
    const int away = use.most_away;
    std::printf("%s, lab containers=8 seed 1: at most %d lids away at once\n", planner.c_str(), away);
    most = std::max(most, away);
  }
  EXPECT_GE(most, 2);
}

}  // namespace
}  // namespace dash
