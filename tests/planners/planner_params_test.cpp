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

TEST(PlannerParams, ThePaperProfileTurnsEveryExtensionOff) {
  const ParamValues paper = resolveParameters("lazy-dash", profileOverrides("lazy-dash", "paper"));
  LazyDashParams p;
  applyParameters(p, paper);
  EXPECT_FALSE(p.motion.straight_first);
  EXPECT_TRUE(p.motion.deep_approach_distances.empty());
  EXPECT_FALSE(p.task.query.remove_round_trips);
  EXPECT_FALSE(p.task.handover_class_bans);
  EXPECT_FALSE(p.scheduler.staggered_arrivals);
  EXPECT_FALSE(p.scheduler.schedule_memo);
  EXPECT_EQ(p.max_transition_resamples, 0);
  EXPECT_EQ(p.validator_rechecks, 0);
  EXPECT_FALSE(p.restart_when_exhausted);
  EXPECT_EQ(paper.at("motion_budget"), "3");  // a budget of the paper's own: left alone
  EXPECT_TRUE(profileOverrides("lazy-dash", "default").empty());
  EXPECT_THROW(profileOverrides("lazy-dash", "fast"), InputError);
  EXPECT_EQ(parametersJson({{"a", "true"}, {"b", "3"}}), R"({"a":true,"b":3})");
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
