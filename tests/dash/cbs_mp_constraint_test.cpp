// CBS-MP's constraints with clock-time intervals (engine/dash/motion_constraint.h): on a plan DaSH
// extracted, the Scheduler keeps a constrained robot's step out of the window (it waits where it stands
// until the window ends, as SIPP's safe intervals), and a window the step does not meet changes
// nothing; a DaSH run that meets a real conflict records its constraints' windows in the results DB.
#include <gtest/gtest.h>

#include <cstdio>

#include "engine/conflict/scheduler.h"
#include "engine/dash/combined_query.h"
#include "engine/dash/dash_planner.h"
#include "engine/dash/motion_constraint.h"
#include "engine/dash/plan_extraction.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"
#include "tests/common/temp_dir.h"
#include "tests/dash/dash_built.h"

namespace dash {
namespace {

using test::Built;
using test::sorting22WithMotion;

/// The first hyperpath of sorting 2/2, scheduled under `node`'s timed constraints (no memo: each build
/// from scratch).
ScheduleResult scheduleUnder(Built& b, const ExtractedPlan& plan, const std::vector<MotionConstraint>& node) {
  const MoveReplanner replan = [&](int r, const JointVector& from, const JointVector& to, const MotionContext& ctx) {
    return b.roadmaps.at(r, ctx.held.holding()).plan(from, to, ctx, Deadline());
  };
  SchedulerParams params;
  params.schedule_memo = false;
  Scheduler scheduler(b.world, b.context, params);
  const std::vector<StepWindow> windows = stepWindows(b.motion->graph(), plan, node);
  scheduler.respect(nullptr, &windows);
  return scheduler.build(plan.plan, plan.transitions, plan.motion, b.space, replan, Deadline());
}

TEST(CbsMpConstraint, AClockTimeWindowMakesTheRobotWaitUntilItEndsAndOutsideItTheEdgeIsUsable) {
  Built& b = sorting22WithMotion();
  CombinedQuery query(*b.motion);
  const HyperpathResult path = query.run({}, {}, Deadline());
  ASSERT_TRUE(path.found());
  const ExtractedPlan plan = extractPlan(*b.motion, path);
  const ScheduleResult free = scheduleUnder(b, plan, {});
  ASSERT_TRUE(free.ok) << free.reason;
  // The plan's last step: its actor, the last move into it (its transition when it did not move).
  const int k = static_cast<int>(plan.plan.steps.size()) - 1;
  const int robot = plan.plan.steps[k].action.robot;
  const auto& moves = plan.step_moves[k][0];
  MotionConstraint c{robot, {}, moves.empty() ? plan.plan.steps[k].arc : moves.back()};
  const double T = free.step_times[k];
  EXPECT_FALSE(c.timed());  // [0, +inf): the query's, never a window
  // A window from just before the transition (the robot is on its way there) to 5 s later.
  c.t0 = T - 0.05;
  c.t1 = T + 5.0;
  ASSERT_TRUE(c.timed());
  ASSERT_EQ(stepWindows(b.motion->graph(), plan, {c}).size(), 1u);
  const ScheduleResult waited = scheduleUnder(b, plan, {c});
  ASSERT_TRUE(waited.ok) << waited.reason;
  // The step happens after the window, and the robot stands still through it.
  EXPECT_GT(waited.step_times[k], c.t1);
  const RobotTrajectory& traj = waited.plan.robots[robot];
  const JointVector still = traj.positionAt(c.t0);
  for (double t = c.t0; t <= c.t1; t += 0.05)
    EXPECT_LE((traj.positionAt(t) - still).cwiseAbs().maxCoeff(), 1e-9) << "moving at t = " << t;
  // The steps before it are as they were.
  for (int j = 0; j < k; ++j) EXPECT_DOUBLE_EQ(waited.step_times[j], free.step_times[j]) << "step " << j;
  // A window after the step (the robot is done with the edge by then): the step is where it was.
  MotionConstraint later = c;
  later.t0 = T + 1.0;
  later.t1 = T + 6.0;
  const ScheduleResult outside = scheduleUnder(b, plan, {later});
  ASSERT_TRUE(outside.ok) << outside.reason;
  EXPECT_DOUBLE_EQ(outside.step_times[k], T);
  EXPECT_DOUBLE_EQ(outside.plan.makespan, free.plan.makespan);
}

TEST(CbsMpConstraint, AWindowIsWrittenIntoItsConstraintEventAsLazyDashWritesOne) {
  Built& b = sorting22WithMotion();
  HyperarcId move;
  for (HyperarcId a : b.motion->graph().hyperarcs())
    if (b.motion->graph().property(a).type == MotionArc::Type::kMove) {
      move = a;
      break;
    }
  ASSERT_TRUE(move.valid());
  MotionConstraint c{b.motion->moveRobot(move), {}, move};
  EXPECT_NE(describe(*b.motion, c).find("at any time"), std::string::npos);
  c.t0 = 1.25;
  c.t1 = 1.5;
  EXPECT_NE(describe(*b.motion, c).find("; t in [1.250, 1.500] s"), std::string::npos) << describe(*b.motion, c);
}

// The break rule's instance (break_rule_run_test.cpp): a scheduler with little room (2 s of delay per
// transition, no composite replanning) leaves conflicts to the constraint tree. Each constraint the
// run learns from a schedule or a contact is recorded with its interval, t0 < t1.
TEST(CbsMpConstraint, ARunWithRealConflictsRecordsEachConstraintsWindowInTheResultsDb) {
  const std::uint64_t seed = 5;
  const Scene scene = test::dashScene("sorting", {{"robots", "3"}, {"objects", "4"}}, seed);
  const DashParams params = test::littleRoomScheduler();
  test::TempDir dir;
  log::ResultsDb db(dir.file("r.db"));
  log::RunMetadata meta;
  meta.family = "sorting";
  meta.planner = "dash";
  meta.seed = seed;
  const std::string uuid = db.beginRun(meta);
  PlanResult r;
  {
    const std::unique_ptr<log::SqliteRecorder> recorder = db.recorder(uuid);
    PlannerSettings settings;
    settings.seed = seed;
    r = DashPlanner(params).solve(scene, settings, Deadline(240.0), recorder.get());
  }
  log::RunSummary summary;
  summary.status = r.outcome == PlanOutcome::kSolved ? log::RunStatus::Solved : log::RunStatus::Timeout;
  db.finishRun(uuid, summary);
  EXPECT_EQ(r.outcome, PlanOutcome::kSolved) << r.message;
  const log::SqlRows rows =
      db.select("SELECT content FROM dash_constraints WHERE kind = 'motion' AND action = 'created'");
  int windows = 0;
  for (const std::vector<log::SqlValue>& row : rows.rows) {
    const std::string content = std::get<std::string>(row.at(0));
    const std::size_t at = content.find("; t in [");
    if (at == std::string::npos) continue;
    double t0 = 0.0, t1 = 0.0;
    ASSERT_EQ(std::sscanf(content.c_str() + at, "; t in [%lf, %lf] s", &t0, &t1), 2) << content;
    EXPECT_LT(t0, t1) << content;
    EXPECT_GE(t0, 0.0) << content;
    ++windows;
  }
  EXPECT_GE(windows, 1) << rows.rows.size() << " motion constraints, none with a window";
}

}  // namespace
}  // namespace dash
