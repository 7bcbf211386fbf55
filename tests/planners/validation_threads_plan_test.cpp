// The same seed gives the same plan with one validator thread or two (issue 23): both planners run the
// plan validator on every schedule and feed its first problem back, so its report must not depend on
// its threads (tests/plan/validation_threads_test.cpp); here the whole run is compared, and the
// `validation_threads` parameter (`dashbench plan --threads N`) is checked. The same parameter sets the
// lanes of conflict resolution's checks (issue 38; engine/conflict/check_pool.h), so one run here uses one
// lane and the other two: the plan, the constraints and the collision checks must still agree.
#include <gtest/gtest.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <variant>
#include <vector>

#include "engine/core/forked_run.h"
#include "engine/core/planner_params.h"
#include "engine/dash/dash_planner.h"
#include "engine/events/memory_sink.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/lazy_dash.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "tests/common/cli_run.h"

namespace dash {
namespace {

/// The certified check gives each thread 64 stretches at least (certified_geometry.cpp).
constexpr std::size_t kStretchesForTwoThreads = 2 * 64;
constexpr double kTimeLimit = 60.0;

struct PlanRun {
  int outcome = -1;  ///< PlanOutcome
  std::string message;
  std::string plan_json;
  std::int64_t checks_eager = 0, checks_lazy = 0, motion_constraints = 0, task_constraints = 0;
  std::int64_t point_times = 0;  ///< distinct trajectory point times: about the validator's stretches
  std::int64_t validation_rechecks = 0, validation_feedbacks = 0;
  std::vector<std::string> constraints;  ///< every constraint's cause, in order (validator messages too)
};

PlanRun solve(const std::string& planner, const Scene& scene, int threads, ParamValues params) {
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = kTimeLimit;
  settings.params = std::move(params);
  settings.params["validation_threads"] = std::to_string(threads);
  log::MemorySink sink;
  const PlanResult result = makePlanner(planner)->solve(scene, settings, Deadline(settings.time_limit), &sink);
  PlanRun run;
  run.outcome = static_cast<int>(result.outcome);
  run.message = result.message;
  run.checks_eager = result.stats.collision_checks_eager;
  run.checks_lazy = result.stats.collision_checks_lazy;
  run.motion_constraints = result.stats.motion_constraints;
  run.task_constraints = result.stats.task_constraints;
  for (const log::Event& e : sink.events())
    if (const auto* c = std::get_if<log::ConstraintEvent>(&e.payload)) run.constraints.push_back(c->conflict);
  run.validation_rechecks = sink.counter("validation_rechecks");
  run.validation_feedbacks = sink.counter("validation_feedbacks");
  if (!result.plan) return run;
  run.plan_json = planToJson(*result.plan);
  std::vector<double> times;
  for (const RobotTrajectory& traj : result.plan->robots)
    for (const TrajectoryPoint& p : traj.points) times.push_back(p.t);
  std::sort(times.begin(), times.end());
  run.point_times = std::unique(times.begin(), times.end()) - times.begin();
  return run;
}

// A run goes through a pipe as length-prefixed texts.
void put(std::string& out, const std::string& text) { out += std::to_string(text.size()) + ":" + text; }
std::string take(const std::string& in, std::size_t& at) {
  const std::size_t colon = in.find(':', at);
  if (colon == std::string::npos) return {};
  const std::size_t n = std::stoul(in.substr(at, colon - at));
  at = colon + 1 + n;
  return in.substr(colon + 1, n);
}
std::string encode(const PlanRun& r) {
  std::string out;
  for (const std::int64_t n : {std::int64_t{r.outcome}, r.checks_eager, r.checks_lazy, r.motion_constraints,
                               r.task_constraints, r.point_times, r.validation_rechecks, r.validation_feedbacks,
                               static_cast<std::int64_t>(r.constraints.size())})
    put(out, std::to_string(n));
  put(out, r.message);
  put(out, r.plan_json);
  for (const std::string& c : r.constraints) put(out, c);
  return out;
}
PlanRun decode(const std::string& in) {
  PlanRun r;
  std::size_t at = 0;
  auto number = [&] { const std::string t = take(in, at); return t.empty() ? std::int64_t{-1} : std::stoll(t); };
  r.outcome = static_cast<int>(number());
  for (std::int64_t* n : {&r.checks_eager, &r.checks_lazy, &r.motion_constraints, &r.task_constraints, &r.point_times,
                          &r.validation_rechecks, &r.validation_feedbacks})
    *n = number();
  const std::int64_t constraints = number();
  r.message = take(in, at);
  r.plan_json = take(in, at);
  for (std::int64_t i = 0; i < constraints; ++i) r.constraints.push_back(take(in, at));
  return r;
}

/// solve() in a child forked from this process. OMPL seeds every RNG the planners do not seed
/// themselves (the pivots of the roadmaps' nearest-neighbour structures, which break ties between
/// equally near vertices) from one process-wide generator whose first seed is the wall clock: two
/// `dashbench plan` processes, or two runs in one process, may differ for that alone. Children forked
/// from one state share the generator's state, so that only the validator's threads differ between the
/// two runs compared here (the parent must not draw from it between the two forks).
PlanRun solveInChild(const std::string& planner, const Scene& scene, int threads, const ParamValues& params) {
  const ForkedRun run = runForked([&] { return encode(solve(planner, scene, threads, params)); });
  EXPECT_TRUE(run.finished) << "the child run did not finish";
  return decode(run.output);
}

void expectSameRunWithOneThreadOrTwo(const std::string& planner, const Scene& scene, const ParamValues& params = {}) {
  // OMPL's process-wide generator is started here, once: both children inherit the same state.
  const ompl::RNG started;
  const PlanRun one = solveInChild(planner, scene, 1, params);
  const PlanRun two = solveInChild(planner, scene, 2, params);
  EXPECT_EQ(one.outcome, static_cast<int>(PlanOutcome::kSolved)) << planner << ": " << one.message;
  EXPECT_FALSE(one.plan_json.empty());
  // The last validation (of this plan) had enough stretches for two threads to share them.
  EXPECT_GE(one.point_times, static_cast<std::int64_t>(kStretchesForTwoThreads));
  EXPECT_EQ(two.outcome, one.outcome);
  EXPECT_EQ(two.plan_json, one.plan_json);
  EXPECT_EQ(two.checks_eager, one.checks_eager);
  EXPECT_EQ(two.checks_lazy, one.checks_lazy);
  EXPECT_EQ(two.motion_constraints, one.motion_constraints);
  EXPECT_EQ(two.task_constraints, one.task_constraints);
  EXPECT_EQ(two.constraints, one.constraints);
  EXPECT_EQ(two.validation_rechecks, one.validation_rechecks);
  EXPECT_EQ(two.validation_feedbacks, one.validation_feedbacks);
}

Scene sortingScene() {
  return generateScenario("sorting", {{"robots", "2"}, {"objects", "4"}}, 1, RobotLibrary::loadDefault());
}

TEST(ValidationThreadsPlan, LazyDashGivesTheSamePlanWithOneThreadOrTwo) {
  expectSameRunWithOneThreadOrTwo("lazy-dash", sortingScene());
}

TEST(ValidationThreadsPlan, DashGivesTheSamePlanWithOneThreadOrTwo) {
  expectSameRunWithOneThreadOrTwo("dash", sortingScene());
}

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string linesStartingWith(const std::string& text, const std::string& prefix) {
  std::string out;
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('\n', at), text.size());
    if (text.compare(at, prefix.size(), prefix) == 0) out += text.substr(at, end - at) + "\n";
    at = end + 1;
  }
  return out;
}

// Two `dashbench plan` processes, one validator thread and two. Wall 4/8 at clearance 0 meets motion
// failures and validator feedback; before query ends were deduplicated in the roadmaps
// (context_lazy_prm.h), GNAT's ties, broken by address, gave 5 different check counts and 2 plans in
// 6 processes.
TEST(ValidationThreadsPlan, LazyDashGivesTheSamePlanInTwoProcesses) {
  const std::string dir = ::testing::TempDir();
  const std::string scene = dir + "/same_plan_wall.json";
  ASSERT_EQ(test::runDashbench("scenario wall robots=4 objects=8 --seed 1 -o '" + scene + "'").exit_code, 0);
  std::vector<std::string> plans, checks;
  for (int threads : {1, 2}) {
    const std::string plan = dir + "/same_plan_wall_" + std::to_string(threads) + ".plan.json";
    const test::CliRun run = test::runDashbench("plan --scene '" + scene + "' --seed 1 --time-limit 120 --set clearance=0 --threads " +
                                                std::to_string(threads) + " --out '" + plan + "'");
    ASSERT_EQ(run.exit_code, 0) << run.output;
    plans.push_back(fileText(plan));
    checks.push_back(linesStartingWith(run.output, "collision checks:") + linesStartingWith(run.output, "sizes:"));
    EXPECT_FALSE(checks.back().empty()) << run.output;
  }
  EXPECT_FALSE(plans[0].empty());
  EXPECT_TRUE(plans[1] == plans[0]) << "the two plans differ (kept in " << dir << ")";
  EXPECT_EQ(checks[1], checks[0]);
}

TEST(ValidationThreadsPlan, BothPlannersNameTheParameterWithTheirDefault) {
  for (const char* planner : {"lazy-dash", "dash"}) {
    const auto& params = plannerParameters(planner);
    const auto it = std::find_if(params.begin(), params.end(), [](const ParamInfo& p) { return p.name == "validation_threads"; });
    ASSERT_NE(it, params.end()) << planner;
    EXPECT_FALSE(it->description.empty());
    EXPECT_FALSE(it->extension()) << "--profile paper must leave it alone";
    EXPECT_EQ(paramInt(resolveParameters(planner, {}), "validation_threads"), 0) << planner;
  }
  SchedulerParams scheduler;
  applySchedulerParameters(scheduler, {{"validation_threads", "2"}});
  EXPECT_EQ(scheduler.threads, 2) << "conflict resolution's lanes follow validation_threads";
  EXPECT_EQ(LazyDashParams{}.validation_threads, 0);
  EXPECT_EQ(DashParams{}.validation_threads, 0);
  LazyDashParams p;
  applyParameters(p, resolveParameters("lazy-dash", {{"validation_threads", "3"}}));
  EXPECT_EQ(p.validation_threads, 3);
  EXPECT_THROW(resolveParameters("dash", {{"validation_threads", "-1"}}), InputError);
}

TEST(ValidationThreadsPlan, TheCommandLineListsAndChecksIt) {
  test::CliRun listed = test::runDashbench("plan --params");
  ASSERT_EQ(listed.exit_code, 0) << listed.output;
  EXPECT_NE(listed.output.find("validation_threads"), std::string::npos) << listed.output;
  test::CliRun help = test::runDashbench("plan --help");
  EXPECT_NE(help.output.find("--threads N"), std::string::npos) << help.output;
  // Checked before the scene is read, as --set validation_threads=x would be.
  test::CliRun bad = test::runDashbench("plan --scene /nonexistent --threads many");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("validation_threads"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace dash
