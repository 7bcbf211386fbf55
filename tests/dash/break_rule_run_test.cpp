// CBS-MP's break rule in a real DaSH run: both branches, growing the roadmaps and growing the
// constraint tree, taken after conflicts that conflict resolution could not repair.
//
// With the default scheduler, Sorting and Wall are solved at the constraint tree's root (the
// scheduler repairs every conflict; the comparison batch never reached the rule), and Shelf-wall and
// Stocking only take the no-hyperpath branch, which can only grow the roadmaps. So this run gives
// the scheduler little room: at most 2 s of delay per transition and no composite replanning. Then
// sorting with 3 robots, 4 objects and seed 5 needs 5 constraint tree nodes: 3 tree branchings and 1
// roadmap growth, and is solved.
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

TEST(DashBreakRule, BothBranchesInARealRun) {
  const std::uint64_t seed = 5;
  const Scene scene = test::dashScene("sorting", {{"robots", "3"}, {"objects", "4"}}, seed);
  DashParams params;
  params.scheduler.max_delay = 2.0;
  params.scheduler.composite_attempts = 0;
  DashPlanner planner(params);
  PlannerSettings settings;
  settings.seed = seed;
  log::MemorySink sink;
  const PlanResult r = planner.solve(scene, settings, Deadline(240.0), &sink);  // ~10 s; work-bounded
  ASSERT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
  const ValidationReport report = validatePlan(scene, *r.plan);
  EXPECT_TRUE(report.valid()) << (report.valid() ? "" : report.problems.front().message);

  const std::int64_t growths = sink.counter("roadmap_growths", -1);
  const std::int64_t branchings = sink.counter("constraint_tree_branchings", -1);
  const std::int64_t nodes = sink.counter("constraint_tree_nodes", -1);
  EXPECT_GE(growths, 1);
  EXPECT_GE(branchings, 1);
  EXPECT_EQ(nodes, r.stats.iterations);
  // Every decision sends the search to another node (or the same one again); the last one is solved.
  EXPECT_GE(nodes, growths + branchings + 1);
  // Every query found a hyperpath and went to conflict resolution: the decisions followed conflicts,
  // not the root's no-hyperpath growth.
  // (Validation runs inside conflict resolution and is booked as its own phase: each one pauses
  // conflict resolution, which then ends once more; those pauses are not resolutions.)
  std::int64_t resolutions = 0;
  std::int64_t first_vertices = -1, last_vertices = -1;
  for (const log::Event& e : sink.events()) {
    if (const auto* p = std::get_if<log::PhaseEvent>(&e.payload); p && p->boundary == log::PhaseBoundary::End) {
      resolutions += p->phase == log::Phase::ConflictResolution;
      resolutions -= p->phase == log::Phase::Validation;
    }
    if (const auto* c = std::get_if<log::CounterEvent>(&e.payload); c && c->name == "roadmap_vertices") {
      if (first_vertices < 0) first_vertices = c->value;
      last_vertices = c->value;
    }
  }
  EXPECT_EQ(resolutions, nodes);
  // A growth adds milestones (and their validated edges) to the roadmaps of the robots involved.
  EXPECT_GT(first_vertices, 0);
  EXPECT_GT(last_vertices, first_vertices);
  EXPECT_EQ(last_vertices, r.stats.roadmap_vertices);
  // A branching forbids motion hyperarcs: motion constraints, each naming its conflict.
  EXPECT_GE(r.stats.motion_constraints, branchings);
  EXPECT_EQ(sink.countConstraints(log::ConstraintKind::Motion, log::ConstraintAction::Created),
            r.stats.motion_constraints);
  for (const log::Event& e : sink.events()) {
    if (const auto* c = std::get_if<log::ConstraintEvent>(&e.payload)) {
      EXPECT_FALSE(c->conflict.empty());
    }
  }
}

}  // namespace
}  // namespace dash
