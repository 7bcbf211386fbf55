// CBS-MP's break rule in a real DaSH run: each branch, growing the roadmaps and growing the
// constraint tree, taken after a conflict that conflict resolution could not repair, and solving.
//
// With the default scheduler, Sorting and Wall are solved at the constraint tree's root (the
// scheduler repairs every conflict; the comparison batch never reached the rule), and Shelf-wall and
// Stocking only take the no-hyperpath branch, which can only grow the roadmaps. So these runs give
// the scheduler little room: at most 2 s of delay per transition and no composite replanning. Then
// sorting with 3 robots, 4 objects and seed 5 meets one conflict the scheduler leaves (ur5e_0 and
// ur5e_2 at a handover, about 21.3 s into the schedule). Since CBS-MP's constraints carry clock-time
// windows (motion_constraint.h), one branching resolves it (the constrained robot waits the window
// out), so the run never meets a second conflict: each branch is taken in a run of its own, the rule
// forced to it (grow_roadmap_probability 0 or 1).
//
// OMPL's samplers are seeded from the run's seed (engine/motion/seeded_ompl.h), so the run is the same
// in any process.
// Budgets are work (milestones), not time: the run is the same on a loaded machine.
#include <gtest/gtest.h>

#include <variant>

#include "engine/dash/dash_planner.h"
#include "engine/events/memory_sink.h"
#include "engine/plan/plan_validator.h"
#include "tests/dash/dash_test_util.h"

namespace dash {
namespace {

struct BreakRuleRun {
  PlanResult result;
  log::MemorySink sink;
};

/// Sorting 3/4 seed 5 with little room in the scheduler and the break rule growing the roadmaps with
/// probability `grow`; solved with a valid plan.
void solve(double grow, BreakRuleRun& run) {
  const std::uint64_t seed = 5;
  const Scene scene = test::dashScene("sorting", {{"robots", "3"}, {"objects", "4"}}, seed);
  DashParams params = test::littleRoomScheduler();
  params.break_rule.grow_roadmap_probability = grow;
  PlannerSettings settings;
  settings.seed = seed;
  run.result = DashPlanner(params).solve(scene, settings, Deadline(600.0), &run.sink);  // work-bounded
  ASSERT_EQ(run.result.outcome, PlanOutcome::kSolved) << run.result.message;
  const ValidationReport report = validatePlan(scene, *run.result.plan);
  EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);
  // Every decision sends the search to another node (or the same one again); the last one is solved.
  const std::int64_t nodes = run.sink.counter("constraint_tree_nodes", -1);
  EXPECT_EQ(nodes, run.result.stats.iterations);
  EXPECT_GE(nodes, run.sink.counter("roadmap_growths", -1) + run.sink.counter("constraint_tree_branchings", -1) + 1);
  // Every query found a hyperpath and went to conflict resolution: the decisions followed conflicts,
  // not the root's no-hyperpath growth.
  // (Validation runs inside conflict resolution and is booked as its own phase: each one pauses
  // conflict resolution, which then ends once more; those pauses are not resolutions.)
  std::int64_t resolutions = 0;
  for (const log::Event& e : run.sink.events())
    if (const auto* p = std::get_if<log::PhaseEvent>(&e.payload); p && p->boundary == log::PhaseBoundary::End) {
      resolutions += p->phase == log::Phase::ConflictResolution;
      resolutions -= p->phase == log::Phase::Validation;
    }
  EXPECT_EQ(resolutions, nodes);
}

TEST(DashBreakRule, GrowingTheRoadmapsAfterARealConflictSolves) {
  BreakRuleRun run;
  solve(1.0, run);
  EXPECT_GE(run.sink.counter("roadmap_growths", -1), 1);
  EXPECT_EQ(run.sink.counter("constraint_tree_branchings", -1), 0);
  // A growth adds milestones (and their validated edges) to the roadmaps of the robots involved.
  std::int64_t first_vertices = -1, last_vertices = -1;
  for (const log::Event& e : run.sink.events())
    if (const auto* c = std::get_if<log::CounterEvent>(&e.payload); c && c->name == "roadmap_vertices") {
      if (first_vertices < 0) first_vertices = c->value;
      last_vertices = c->value;
    }
  EXPECT_GT(first_vertices, 0);
  EXPECT_GT(last_vertices, first_vertices);
  EXPECT_EQ(last_vertices, run.result.stats.roadmap_vertices);
}

TEST(DashBreakRule, GrowingTheConstraintTreeAfterARealConflictSolves) {
  BreakRuleRun run;
  solve(0.0, run);
  EXPECT_EQ(run.sink.counter("roadmap_growths", -1), 0);
  const std::int64_t branchings = run.sink.counter("constraint_tree_branchings", -1);
  EXPECT_GE(branchings, 1);
  // A branching adds CBS-MP constraints, one child each, each naming its conflict and its window.
  EXPECT_GE(run.result.stats.motion_constraints, branchings);
  EXPECT_EQ(run.sink.countConstraints(log::ConstraintKind::Motion, log::ConstraintAction::Created),
            run.result.stats.motion_constraints);
  for (const log::Event& e : run.sink.events())
    if (const auto* c = std::get_if<log::ConstraintEvent>(&e.payload)) {
      EXPECT_FALSE(c->conflict.empty());
      EXPECT_NE(c->content.find("; t in ["), std::string::npos) << c->content;
    }
}

}  // namespace
}  // namespace dash
