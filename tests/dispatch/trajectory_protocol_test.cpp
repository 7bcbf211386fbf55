// Arm trajectories from plans (velocities, the Hermite curve, speeds) and the server-agent codecs.
#include <gtest/gtest.h>

#include <cmath>

#include "dispatch_test_util.h"
#include "engine/core/check.h"
#include "engine/plan/plan_validator.h"
#include "server/dispatch/arm_trajectory.h"
#include "server/dispatch/dispatch_protocol.h"

namespace dash::dispatch {
namespace {

JointVector j2(double a, double b) {
  JointVector q(2);
  q << a, b;
  return q;
}

TEST(ArmTrajectory, VelocitiesStopAtCornersAndKeepConstantRuns) {
  // Straight run at constant speed through point 1, a corner at point 2, a dwell, then back.
  const std::vector<JointVector> q = {j2(0, 0), j2(1, 0.5), j2(2, 1), j2(2, 0), j2(2, 0)};
  const std::vector<double> t = {0, 1, 2, 3, 4};
  const auto v = velocitiesForPlanPath(q, t);
  EXPECT_TRUE(v[0].isZero());
  EXPECT_TRUE(v[1].isApprox(j2(1, 0.5)));
  EXPECT_TRUE(v[2].isZero());  // corner
  EXPECT_TRUE(v[3].isZero());  // into a dwell
  EXPECT_TRUE(v[4].isZero());
}

TEST(ArmTrajectory, FollowsThePlanLinesAndHitsEveryPointOnTime) {
  Plan plan;
  plan.robots.push_back({"r", {"a", "b"},
                         {{0.0, j2(0, 0)}, {1.0, j2(1, 0.5)}, {2.0, j2(2, 1)}, {3.0, j2(3, 1.5)}, {4.0, j2(3, -0.5)}}});
  plan.events.push_back({PlanEvent::Type::kGrasp, 2.5, "r", "o"});
  plan.events.push_back({PlanEvent::Type::kRelease, 1.5, "r", "o"});
  const ArmTrajectory arm = armTrajectoryFromPlan(plan, "r", 2.0);  // half speed
  ASSERT_EQ(arm.points.size(), 5u);
  EXPECT_DOUBLE_EQ(arm.duration(), 8.0);
  ASSERT_EQ(arm.gripper.size(), 2u);
  EXPECT_DOUBLE_EQ(arm.gripper[0].t, 3.0);  // sorted, scaled
  EXPECT_EQ(arm.gripper[0].action, GripperCommand::Action::kRelease);
  for (const auto& p : arm.points) EXPECT_TRUE(arm.positionAt(p.time_from_start).isApprox(p.positions));
  // Between two points inside a constant-speed run: exactly linear.
  EXPECT_TRUE(arm.positionAt(3.0).isApprox(j2(1.5, 0.75)));
  EXPECT_TRUE(arm.velocityAt(3.0).isApprox(j2(0.5, 0.25)));
  // Into and out of the corner: on the line x = 3 (velocities parallel to the segment), 1.5x mean speed mid-way.
  for (double t = 6.0; t <= 8.0; t += 0.25) EXPECT_NEAR(arm.positionAt(t)[0], 3.0, 1e-12);
  EXPECT_TRUE(arm.velocityAt(7.0).isApprox(j2(0, -1.5)));
  EXPECT_TRUE(arm.positionAt(-1.0).isApprox(j2(0, 0)));
  EXPECT_TRUE(arm.positionAt(99.0).isApprox(j2(3, -0.5)));

  const PeakSpeed peak = peakSpeed(arm, j2(1.0, 1.0));
  EXPECT_NEAR(peak.speed, 1.5, 1e-12);
  EXPECT_EQ(peak.segment, 3);
  EXPECT_EQ(peak.joint, 1);
  EXPECT_THROW(armTrajectoryFromPlan(plan, "nobody"), InputError);
}

TEST(ArmTrajectory, StructuralProblems) {
  ArmTrajectory t;
  t.joint_names = {"a", "b"};
  EXPECT_NE(structuralProblem(t, 2), "");
  t.points = {{j2(0, 0), j2(0, 0), 0.0}, {j2(1, 0), j2(0, 0), 1.0}};
  EXPECT_EQ(structuralProblem(t, 2), "");
  EXPECT_NE(structuralProblem(t, 3), "");
  t.points[1].time_from_start = 0.0;
  EXPECT_NE(structuralProblem(t, 2).find("does not increase"), std::string::npos);
  t.points[1].time_from_start = 1.0;
  t.points[1].positions[0] = NAN;
  EXPECT_NE(structuralProblem(t, 2).find("NaN"), std::string::npos);
}

TEST(Protocol, CodecsRoundTrip) {
  TrajectoryCommand c;
  c.dispatch_id = "d1-1";
  c.trajectory.robot = "ur5e_0";
  c.trajectory.joint_names = {"a", "b"};
  c.trajectory.points = {{j2(0, 0), j2(0, 0), 0.0}, {j2(0.25, -1), j2(0.5, 0), 1.5}};
  c.trajectory.gripper = {{1.0, GripperCommand::Action::kGrasp, "obj_0"}};
  c.limits.start_tolerance = 0.02;
  const TrajectoryCommand back = parseTrajectoryCommand(trajectoryCommandToJson(c));
  EXPECT_EQ(back.dispatch_id, "d1-1");
  EXPECT_EQ(back.trajectory.joint_names, c.trajectory.joint_names);
  ASSERT_EQ(back.trajectory.points.size(), 2u);
  EXPECT_TRUE(back.trajectory.points[1].velocities.isApprox(j2(0.5, 0)));
  EXPECT_DOUBLE_EQ(back.trajectory.points[1].time_from_start, 1.5);
  EXPECT_EQ(back.trajectory.gripper[0].object, "obj_0");
  EXPECT_DOUBLE_EQ(back.limits.start_tolerance, 0.02);

  AgentReport r;
  r.session = "s4";
  r.driver = "ur";
  r.ready = true;
  r.status = ArmStatus::kFailed;
  r.result = ResultCode::kPathToleranceViolated;
  r.message = "robot said 2";
  r.samples.push_back({123456789012LL, j2(1, 2), j2(0, 0)});
  const AgentReport rb = parseAgentReport(agentReportToJson(r));
  EXPECT_EQ(rb.session, "s4");
  EXPECT_EQ(rb.status, ArmStatus::kFailed);
  EXPECT_EQ(rb.result, ResultCode::kPathToleranceViolated);
  ASSERT_EQ(rb.samples.size(), 1u);
  EXPECT_EQ(rb.samples[0].t_us, 123456789012LL);
  EXPECT_EQ(parseStartCommand(startCommandToJson({"d", 42})).start_time_us, 42);
  EXPECT_EQ(parseAbortCommand(abortCommandToJson({"d", "why"})).reason, "why");
  EXPECT_EQ(parseServerTime("{\"server_time_us\": 77}"), 77);
  EXPECT_THROW(parseAgentReport("{\"status\": \"idle\"}"), InputError);  // no session
  EXPECT_THROW(parseAgentReport("{\"session\": \"s\", \"status\": \"dancing\"}"), InputError);
  EXPECT_THROW(parseTrajectoryCommand("[1, 2]"), InputError);
}

TEST(Protocol, SseParserHandlesAnyChunking) {
  const std::string stream = formatSse("hello", "{\"a\":1}") + ": comment\n\n" + "event: ping\r\ndata: x\r\n\r\n" +
                             "data: line1\ndata: line2\n\n";
  for (std::size_t chunk : {1u, 3u, 7u, 1000u}) {
    SseParser parser;
    std::vector<SseEvent> events;
    for (std::size_t i = 0; i < stream.size(); i += chunk) {
      auto got = parser.feed(stream.data() + i, std::min(chunk, stream.size() - i));
      events.insert(events.end(), got.begin(), got.end());
    }
    ASSERT_EQ(events.size(), 3u) << "chunk " << chunk;
    EXPECT_EQ(events[0].event, "hello");
    EXPECT_EQ(events[0].data, "{\"a\":1}");
    EXPECT_EQ(events[1].event, "ping");
    EXPECT_EQ(events[1].data, "x");
    EXPECT_EQ(events[2].event, "message");
    EXPECT_EQ(events[2].data, "line1\nline2");
  }
}

TEST(TestPlan, IsValidForItsScene) {
  // The fixtures' plans pass the project's validator (the pre-flight would refuse them otherwise).
  for (int extra : {1, 2}) {
    const Scene scene = test::multiArmScene(extra);
    const Plan plan = test::multiArmPlan(scene);
    const ValidationReport report = validatePlan(scene, plan);
    EXPECT_TRUE(report.valid()) << report.summary();
  }
}

}  // namespace
}  // namespace dash::dispatch
