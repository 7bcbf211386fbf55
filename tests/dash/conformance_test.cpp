// One conformance suite for both planners: the same small scenes through makePlanner("lazy-dash") and
// makePlanner("dash"), every solved plan through the validator, every reported size against the event
// stream. A case a planner is expected to solve and does not is a failure, never a skip.
#include <gtest/gtest.h>

#include <ostream>
#include <string>
#include <vector>

#include "engine/events/memory_sink.h"
#include "engine/plan/plan_validator.h"
#include "engine/planners/planner.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

using KeyValues = std::vector<std::pair<std::string, std::string>>;

// time_limit: generous for a loaded 2-core CI machine (a run stops as soon as it is solved).
struct Case {
  std::string name;
  std::string family;
  KeyValues params;
  double time_limit;
  bool lazy_must_solve;
  bool dash_must_solve;
};

std::string caseName(const Case& c) { return c.name; }
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

struct PlannerRun {
  PlanResult result;
  log::MemorySink events;
};

void runPlanner(const std::string& planner, const Scene& scene, double time_limit, PlannerRun& run) {
  auto p = makePlanner(planner);
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = time_limit;
  run.result = p->solve(scene, settings, Deadline(time_limit), &run.events);
}

// What both planners promise about every run, solved or not.
void expectConformingRun(const std::string& planner, const Scene& scene, const PlannerRun& run) {
  const PlanResult& r = run.result;
  SCOPED_TRACE(planner + " on " + scene.name + ": " + toString(r.outcome) + " (" + r.message + ")");
  if (r.outcome == PlanOutcome::kSolved) {
    ASSERT_TRUE(r.plan.has_value());
    EXPECT_EQ(r.plan->planner, planner);
    const ValidationReport report = validatePlan(scene, *r.plan);
    EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);
    EXPECT_GT(r.stats.makespan, 0.0);
  } else {
    EXPECT_FALSE(r.plan.has_value());
    EXPECT_FALSE(r.message.empty());
  }
  // Sizes in the result are the sizes the event stream describes.
  const auto& s = r.stats.sizes;
  EXPECT_EQ(run.events.count(log::Layer::Task, log::ElementKind::Vertex), static_cast<std::int64_t>(s.task_vertices));
  EXPECT_EQ(run.events.count(log::Layer::Task, log::ElementKind::Hyperarc), static_cast<std::int64_t>(s.task_hyperarcs));
  EXPECT_EQ(run.events.count(log::Layer::Motion, log::ElementKind::Vertex), static_cast<std::int64_t>(s.motion_vertices));
  EXPECT_EQ(run.events.count(log::Layer::Motion, log::ElementKind::Hyperarc),
            static_cast<std::int64_t>(s.motion_hyperarcs));
  EXPECT_EQ(run.events.count(log::Layer::MotionExtended, log::ElementKind::Vertex),
            static_cast<std::int64_t>(s.motion_extended_vertices));
  EXPECT_EQ(run.events.count(log::Layer::MotionExtended, log::ElementKind::Hyperarc),
            static_cast<std::int64_t>(s.motion_extended_hyperarcs));
  EXPECT_GT(s.task_vertices, 0u);
  // Phase timings: the result's totals are the sums of the stream's phase events.
  for (int p = 0; p < log::kPhaseCount; ++p)
    EXPECT_NEAR(run.events.phaseSeconds(static_cast<log::Phase>(p)), r.stats.phase_seconds[p], 1e-9)
        << log::toString(static_cast<log::Phase>(p));
  EXPECT_EQ(run.events.counter("collision_checks_lazy", -1), r.stats.collision_checks_lazy);
  EXPECT_GE(run.events.counter("roadmap_vertices", -1), 0);
  EXPECT_GE(run.events.counter("collision_checks_lazy", -1), 0);
  EXPECT_GT(r.stats.phase_seconds[static_cast<int>(log::Phase::TaskConstruction)], 0.0);
}

// DaSH's own promises: an exhaustive motion hypergraph built before any query, eager checks, and no
// task-level feedback of any kind.
void expectDashRun(const PlannerRun& run) {
  const PlanResult& r = run.result;
  EXPECT_GT(r.stats.sizes.motion_vertices, 0u);
  EXPECT_GT(r.stats.sizes.motion_hyperarcs, r.stats.sizes.motion_vertices);
  EXPECT_EQ(r.stats.sizes.task_extended_vertices, 0u);
  EXPECT_GT(r.stats.collision_checks_eager, 0);
  EXPECT_EQ(run.events.counter("collision_checks_eager", -1), r.stats.collision_checks_eager);
  EXPECT_GT(r.stats.roadmap_vertices, 0);
  EXPECT_GT(run.events.countHyperarcs(log::Layer::Motion, "move"), 0);
  EXPECT_EQ(run.events.countConstraints(log::ConstraintKind::Frontier, log::ConstraintAction::Created), 0);
  EXPECT_EQ(run.events.countConstraints(log::ConstraintKind::History, log::ConstraintAction::Created), 0);
  EXPECT_EQ(run.events.countConstraints(log::ConstraintKind::Interaction, log::ConstraintAction::Created), 0);
  EXPECT_EQ(run.events.countTaskSpaceExpansions(), 0);
  EXPECT_EQ(run.events.countConstraints(log::ConstraintKind::Motion, log::ConstraintAction::Created),
            r.stats.motion_constraints);
  EXPECT_GT(r.stats.phase_seconds[static_cast<int>(log::Phase::MotionConstruction)], 0.0);
  EXPECT_EQ(run.events.counter("roadmap_vertices", -1), r.stats.roadmap_vertices);
  EXPECT_EQ(run.events.counter("roadmap_edges", -1), r.stats.roadmap_edges);
  // The constraint tree and CBS-MP's break rule are in the stream too.
  EXPECT_EQ(run.events.counter("constraint_tree_nodes", -1), r.stats.iterations);
  EXPECT_GE(run.events.counter("roadmap_growths", -1), 0);
  EXPECT_GE(run.events.counter("constraint_tree_branchings", -1), 0);
}

class Conformance : public ::testing::TestWithParam<Case> {};

TEST_P(Conformance, LazyDash) {
  const Case& c = GetParam();
  const Scene scene = test::dashScene(c.family, c.params);
  PlannerRun run;
  runPlanner("lazy-dash", scene, c.time_limit, run);
  expectConformingRun("lazy-dash", scene, run);
  if (c.lazy_must_solve) {
    EXPECT_EQ(run.result.outcome, PlanOutcome::kSolved) << "lazy-dash did not solve " << c.name << ": "
                                                        << run.result.message;
  }
}

TEST_P(Conformance, Dash) {
  const Case& c = GetParam();
  const Scene scene = test::dashScene(c.family, c.params);
  PlannerRun run;
  runPlanner("dash", scene, c.time_limit, run);
  expectConformingRun("dash", scene, run);
  expectDashRun(run);
  if (c.dash_must_solve) {
    EXPECT_EQ(run.result.outcome, PlanOutcome::kSolved) << "dash did not solve " << c.name << ": "
                                                        << run.result.message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, Conformance,
    ::testing::Values(Case{"sorting_r2_o2", "sorting", {{"robots", "2"}, {"objects", "2"}}, 30.0, true, true},
                      Case{"sorting_r4_o8", "sorting", {{"robots", "4"}, {"objects", "8"}}, 150.0, true, true}),
    [](const ::testing::TestParamInfo<Case>& info) { return caseName(info.param); });

TEST(ConformanceNames, BothPlannersAreRegistered) {
  const std::vector<std::string> names = plannerNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "lazy-dash"), names.end());
  EXPECT_NE(std::find(names.begin(), names.end(), "dash"), names.end());
  EXPECT_EQ(makePlanner("dash")->name(), "dash");
  EXPECT_THROW(makePlanner("dash-star"), InputError);
}

}  // namespace
}  // namespace dash
