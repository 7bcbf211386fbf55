// DaSH's named parameters (engine/dash/dash_params.h): defaults equal to DashParams' own, every
// addition beyond the DaSH paper off in --profile paper, the CLI listing them, and `--profile paper`
// on small scenes of every family: solved with a valid plan or out of time, never "infeasible".
#include <gtest/gtest.h>

#include "engine/dash/dash_planner.h"
#include "engine/plan/plan_validator.h"
#include "tests/common/cli_run.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

const char* const kExtensions[] = {"greedy_move_pruning", "one_object_pass",          "complete_pass",
                                   "stranding_prune",     "targeted_handovers",       "approach_line_preference",
                                   "deep_backoffs",       "shortcutting",             "validator_rechecks"};

TEST(DashParams, EveryAdditionBeyondDashIsANamedExtension) {
  const std::vector<ParamInfo>& params = plannerParameters("dash");
  for (const char* name : kExtensions) {
    const auto it = std::find_if(params.begin(), params.end(), [&](const ParamInfo& p) { return p.name == name; });
    ASSERT_NE(it, params.end()) << name;
    EXPECT_TRUE(it->extension()) << name;
    EXPECT_FALSE(it->description.empty()) << name;
  }
}

TEST(DashParams, DefaultsAreThePlannersOwn) {
  DashParams applied;
  applyDashParameters(applied, resolveParameters("dash", {}));
  const DashParams plain;
  EXPECT_EQ(applied.query.prune_moves, plain.query.prune_moves);
  EXPECT_EQ(applied.query.one_object_pass, plain.query.one_object_pass);
  EXPECT_EQ(applied.query.complete_pass, plain.query.complete_pass);
  EXPECT_EQ(applied.query.stranding_prune, plain.query.stranding_prune);
  EXPECT_EQ(applied.transitions.targeted_handover_poses, plain.transitions.targeted_handover_poses);
  EXPECT_EQ(applied.transitions.approach_line, plain.transitions.approach_line);
  EXPECT_EQ(applied.transitions.deep_approach_distances, plain.transitions.deep_approach_distances);
  EXPECT_EQ(applied.shortcutting, plain.shortcutting);
  EXPECT_EQ(applied.validator_rechecks, plain.validator_rechecks);
  EXPECT_EQ(applied.empty_roadmap_samples, plain.empty_roadmap_samples);
  EXPECT_EQ(applied.holding_roadmap_samples, plain.holding_roadmap_samples);
  EXPECT_EQ(applied.growth_samples, plain.growth_samples);
  EXPECT_EQ(applied.break_rule.grow_roadmap_probability, plain.break_rule.grow_roadmap_probability);
}

TEST(DashParams, ThePaperProfileIsDashAsPublished) {
  DashParams p;
  applyDashParameters(p, resolveParameters("dash", profileOverrides("dash", "paper")));
  EXPECT_FALSE(p.query.prune_moves);
  EXPECT_FALSE(p.query.one_object_pass);
  EXPECT_FALSE(p.query.complete_pass);
  EXPECT_FALSE(p.query.stranding_prune);
  // Every handover pose for every grasp chain.
  EXPECT_EQ(p.transitions.targeted_handover_poses, p.transitions.handover_poses);
  EXPECT_FALSE(p.transitions.approach_line);
  EXPECT_TRUE(p.transitions.deep_approach_distances.empty());
  EXPECT_FALSE(p.shortcutting);
  EXPECT_EQ(p.validator_rechecks, 0);
  EXPECT_FALSE(p.scheduler.schedule_memo);
  // Budgets are left alone.
  EXPECT_EQ(p.empty_roadmap_samples, DashParams{}.empty_roadmap_samples);
}

TEST(DashParams, TheCliListsThemAndTakesTheProfile) {
  test::CliRun r = test::runDashbench("plan --params --planner dash");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : kExtensions) EXPECT_NE(r.output.find(name), std::string::npos) << name;
  r = test::runDashbench("plan --scene /nonexistent --planner dash --profile paper --set complete_pass=maybe");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("complete_pass"), std::string::npos) << r.output;
}

// DaSH as published on a small scene of each family: a valid plan or its deadline, never "infeasible"
// (every generated scene is feasible), never an internal error.
TEST(DashPaperProfile, SmallScenesOfEveryFamilySolveOrRunToTheDeadline) {
  const std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> cases = {
      {"sorting", {{"robots", "2"}, {"objects", "2"}}},
      {"wall", {{"robots", "4"}, {"walls", "1"}, {"objects", "2"}}},
      {"shelf-wall", {{"robots", "2"}, {"objects", "2"}}},
      {"stocking", {{"layers", "2"}, {"objects", "4"}}},
      {"lab", {{"containers", "2"}}},
  };
  for (const auto& [family, kv] : cases) {
    SCOPED_TRACE(family);
    const Scene scene = test::dashScene(family, kv);
    DashPlanner planner;
    PlannerSettings settings;
    settings.time_limit = 15.0;
    settings.params = profileOverrides("dash", "paper");
    const PlanResult r = planner.solve(scene, settings, Deadline(settings.time_limit), nullptr);
    EXPECT_TRUE(r.outcome == PlanOutcome::kSolved || r.outcome == PlanOutcome::kTimeout)
        << toString(r.outcome) << ": " << r.message;
    if (r.plan) {
      EXPECT_TRUE(validatePlan(scene, *r.plan).valid());
    }
    EXPECT_EQ(r.message.find("internal error"), std::string::npos) << r.message;
  }
}

// Where the paper profile solves (issue 37's small scenes; CPU seconds on seed 1 in the issue report):
// sorting 2/2, wall 5/1/5 and lab 4 solve with a plan the validator accepts. Work-bounded runs: the
// deadline is generous for a loaded machine, not a speed goal (benchmarks hold those).
TEST(DashPaperProfile, SortingWallAndLabSolveWithValidPlans) {
  const std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> cases = {
      {"sorting", {{"robots", "2"}, {"objects", "2"}}},
      {"wall", {{"robots", "5"}, {"walls", "1"}, {"objects", "5"}}},
      {"lab", {{"containers", "4"}}},
  };
  for (const auto& [family, kv] : cases) {
    SCOPED_TRACE(family);
    const Scene scene = test::dashScene(family, kv);
    PlannerSettings settings;
    settings.seed = 1;
    settings.time_limit = 900.0;
    settings.params = profileOverrides("dash", "paper");
    const PlanResult r = DashPlanner().solve(scene, settings, Deadline(settings.time_limit), nullptr);
    ASSERT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
    ASSERT_TRUE(r.plan.has_value());
    const ValidationReport report = validatePlan(scene, *r.plan);
    EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);
  }
}

}  // namespace
}  // namespace dash
