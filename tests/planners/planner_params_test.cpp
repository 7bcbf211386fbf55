// Named planner parameters: defaults equal to the planner's own, bad names and values rejected naming
// the parameter, the paper profile turning every extension off, and the CLI's --params / --set.
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <string>

#include "engine/core/planner_params.h"
#include "engine/planners/lazy_dash.h"
#include "tests/common/cli_run.h"

namespace dash {
namespace {

std::string messageOf(const std::string& planner, const ParamValues& values) {
  try {
    resolveParameters(planner, values);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PlannerParams, DefaultsAreThePlannersOwn) {
  const ParamValues defaults = resolveParameters("lazy-dash", {});
  LazyDashParams applied;
  applyParameters(applied, defaults);
  const LazyDashParams plain;
  EXPECT_EQ(applied.motion.straight_first, plain.motion.straight_first);
  EXPECT_EQ(applied.motion.deep_approach_distances, plain.motion.deep_approach_distances);
  EXPECT_EQ(applied.motion.roadmap.query_samples, plain.motion.roadmap.query_samples);
  EXPECT_EQ(applied.max_transition_resamples, plain.max_transition_resamples);
  EXPECT_EQ(applied.validator_rechecks, plain.validator_rechecks);
  EXPECT_EQ(applied.validation_feedbacks, plain.validation_feedbacks);
  EXPECT_EQ(applied.motion_budget, plain.motion_budget);
  EXPECT_EQ(applied.restart_when_exhausted, plain.restart_when_exhausted);
  EXPECT_EQ(applied.task.query.remove_round_trips, plain.task.query.remove_round_trips);
  EXPECT_EQ(applied.scheduler.schedule_memo, plain.scheduler.schedule_memo);
  EXPECT_EQ(applied.clearance, plain.clearance);
  EXPECT_EQ(plain.clearance, kDefaultPlanningClearance);
  for (const ParamInfo& p : plannerParameters("lazy-dash")) EXPECT_FALSE(p.description.empty()) << p.name;
  // Both planners name their clearance, with the collision layer's default.
  for (const char* planner : {"lazy-dash", "dash"})
    EXPECT_EQ(paramReal(resolveParameters(planner, {}), "clearance"), kDefaultPlanningClearance) << planner;
  applyParameters(applied, {{"clearance", "0.005"}});
  EXPECT_EQ(applied.clearance, 0.005);
  EXPECT_THROW(resolveParameters("dash", {{"clearance", "0.5"}}), InputError);  // above the 5 cm range
}

TEST(PlannerParams, BadNamesAndValuesNameTheParameter) {
  EXPECT_NE(messageOf("lazy-dash", {{"no_such_thing", "1"}}).find("no_such_thing"), std::string::npos);
  EXPECT_NE(messageOf("lazy-dash", {{"straight_first", "maybe"}}).find("straight_first"), std::string::npos);
  EXPECT_NE(messageOf("lazy-dash", {{"motion_budget", "0"}}).find("motion_budget"), std::string::npos);
  EXPECT_NE(messageOf("lazy-dash", {{"motion_budget", "2.5"}}).find("motion_budget"), std::string::npos);
  EXPECT_NE(messageOf("lazy-dash", {{"transition_resamples", std::string(100, '9')}}).find("transition_resamples"),
            std::string::npos);
  EXPECT_THROW(plannerParameters("nope"), InputError);
  EXPECT_THROW(parseAssignment("straight_first"), InputError);
  EXPECT_EQ(resolveParameters("lazy-dash", {{"straight_first", "off"}}).at("straight_first"), "false");
}

// --profile paper is the published algorithm: what the paper describes stays on (transition
// resampling, global sampling after local refinement, its vertices joining the roadmap, growth of the
// budgets, constraints lifted when new samples come, conflict resolution's replanning), everything
// beyond it goes off, and budgets the paper has without a value are left alone.
TEST(PlannerParams, ThePaperProfileIsThePublishedAlgorithm) {
  const ParamValues paper = resolveParameters("lazy-dash", profileOverrides("lazy-dash", "paper"));
  LazyDashParams p;
  applyParameters(p, paper);
  // Beyond the paper: off.
  EXPECT_FALSE(p.motion.straight_first);
  EXPECT_TRUE(p.motion.deep_approach_distances.empty());
  EXPECT_FALSE(p.motion.roadmap.simplify);
  EXPECT_FALSE(p.task.query.remove_round_trips);
  EXPECT_FALSE(p.task.handover_class_bans);
  EXPECT_FALSE(p.task.move_out_one_grasp);
  EXPECT_EQ(p.task.conflicts.chain_location_resamples, 0);
  EXPECT_FALSE(p.task.conflicts.prefer_free_approach);
  EXPECT_FALSE(p.scheduler.staggered_arrivals);
  EXPECT_FALSE(p.scheduler.schedule_memo);
  EXPECT_FALSE(p.scheduler.idle_arms_home);
  EXPECT_FALSE(p.scheduler.parking);
  EXPECT_EQ(p.validator_rechecks, 0);
  EXPECT_EQ(p.validation_feedbacks, 0);
  // Described by the paper: on.
  EXPECT_EQ(p.max_transition_resamples, 2);  // "resampling is performed to search for valid alternatives"
  EXPECT_TRUE(p.motion.global_sampling);     // "additional vertices are sampled globally"
  EXPECT_TRUE(p.motion.roadmap.keep_tree_paths);
  EXPECT_TRUE(p.budget_growth);              // "with increasing budgets"
  EXPECT_TRUE(p.restart_when_exhausted);     // constraints "can be lifted when new ... samples are introduced"
  EXPECT_TRUE(p.scheduler.conflict_replanning);
  EXPECT_EQ(paper.at("motion_budget"), "3");  // a budget of the paper's own: left alone
  // Every parameter says where it comes from.
  for (const ParamInfo& info : plannerParameters("lazy-dash")) EXPECT_FALSE(info.source.empty()) << info.name;
  EXPECT_TRUE(profileOverrides("lazy-dash", "default").empty());
  EXPECT_THROW(profileOverrides("lazy-dash", "fast"), InputError);
  EXPECT_EQ(parametersJson({{"a", "true"}, {"b", "3"}}), R"({"a":true,"b":3})");
}

// The heuristics that had no name are named parameters now, applied where they act.
TEST(PlannerParams, FormerlyHiddenHeuristicsAreNamedAndApplied) {
  LazyDashParams p;
  applyParameters(p, resolveParameters("lazy-dash", {{"move_outs_per_object", "5"}, {"ban_queries", "2"},
                                                     {"ban_lifts", "7"}, {"handover_base_distance", "1.2"},
                                                     {"max_task_plans", "9"}, {"conflict_replanning", "false"}}));
  EXPECT_EQ(p.task.max_extra_locations_per_object, 5);
  EXPECT_EQ(p.task.max_ban_queries, 2);
  EXPECT_EQ(p.task.max_ban_lifts, 7);
  EXPECT_EQ(p.task.reachability.max_handover_base_distance, 1.2);
  EXPECT_EQ(p.max_task_plans, 9);
  EXPECT_FALSE(p.scheduler.conflict_replanning);
  const std::string table = parametersMarkdown("lazy-dash");
  EXPECT_NE(table.find("| `handover_base_distance` | 1.8 | same (a budget) |"), std::string::npos) << table;
  EXPECT_NE(table.find("| `straight_first` | true | false | beyond the paper |"), std::string::npos) << table;
}

int run(const std::string& args, std::string* out) {
  test::CliRun r = test::runDashbench(args);
  *out += r.output;
  return r.exit_code;
}

TEST(PlannerParamsCli, ListsSetsAndRejects) {
  std::string out;
  ASSERT_EQ(run("plan --params", &out), 0) << out;
  EXPECT_NE(out.find("straight_first"), std::string::npos);
  EXPECT_NE(out.find("dash parameters"), std::string::npos);
  out.clear();
  EXPECT_EQ(run("plan --scene /nonexistent --set no_such_thing=1", &out), 2);
  EXPECT_NE(out.find("no_such_thing"), std::string::npos) << out;
  out.clear();
  EXPECT_EQ(run("plan --scene /nonexistent --profile paper --set straight_first=maybe", &out), 2);
  EXPECT_NE(out.find("straight_first"), std::string::npos) << out;
}

}  // namespace
}  // namespace dash
