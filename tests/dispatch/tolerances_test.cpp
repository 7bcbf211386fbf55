// Per-joint tolerances (tolerances.h) and how a request and the agent protocol carry them, including
// requests that attack the parser.
#include "server/dispatch/tolerances.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "engine/plan/plan.h"
#include "server/dispatch/dispatch_json.h"
#include "server/dispatch/dispatch_protocol.h"

namespace dash::dispatch {
namespace {

JointVector v3(double a, double b, double c) { return (JointVector(3) << a, b, c).finished(); }

TEST(Tolerances, ResolvePerJointNameWithADefault) {
  const ToleranceSpec spec{0.2, {{"elbow", 0.05}, {"unknown", 9.0}}};
  EXPECT_EQ(spec.resolve({"base", "elbow", "wrist"}), v3(0.2, 0.05, 0.2));
  EXPECT_THROW((ToleranceSpec{-0.1, {}}.validate("t")), InputError);
  EXPECT_THROW((ToleranceSpec{0.1, {{"elbow", -1.0}}}.validate("t")), InputError);
}

TEST(Tolerances, TheWorstJointOverItsOwnToleranceIsReported) {
  // Joint 0 has the largest error but a loose tolerance; joint 2 exceeds its tight one by the most.
  const ToleranceCheck c = checkTolerance(v3(0.5, 0.0, 0.1), v3(0.0, 0.0, 0.0), v3(1.0, 0.1, 0.02));
  EXPECT_TRUE(c.violated);
  EXPECT_EQ(c.joint, 2);
  EXPECT_DOUBLE_EQ(c.error, 0.1);
  EXPECT_DOUBLE_EQ(c.tolerance, 0.02);
  EXPECT_EQ(describeViolation(c, {"a", "b", "c"}, "path", 1.25),
            "joint 2 (c) 0.1000 rad off at t=1.250 s (path tolerance 0.0200)");
  // 0 is not checked (as in ros2_control); within tolerance: the largest error, not violated.
  EXPECT_FALSE(checkTolerance(v3(5.0, 0.0, 0.0), v3(0, 0, 0), v3(0.0, 0.1, 0.1)).violated);
  const ToleranceCheck ok = checkTolerance(v3(0.01, 0.05, 0.0), v3(0, 0, 0), v3(0.1, 0.1, 0.1));
  EXPECT_FALSE(ok.violated);
  EXPECT_EQ(ok.joint, 1);
  // A NaN state is never within tolerance; a wrong size is a violation.
  EXPECT_TRUE(checkTolerance(v3(std::nan(""), 0, 0), v3(0, 0, 0), v3(0.1, 0.1, 0.1)).violated);
  EXPECT_TRUE(checkTolerance(JointVector::Zero(2), v3(0, 0, 0), v3(0.1, 0.1, 0.1)).violated);
}

std::string request(const std::string& options) { return R"({"run_id": "r1", "options": )" + options + "}"; }

TEST(Tolerances, RequestOptionsCarryThemPerDispatch) {
  const DispatchRequestBody b =
      parseDispatchRequest(request(R"({"path_tolerance": {"all": 0.3, "wrist_3_joint": 0.1}, "goal_tolerance": 0.005,
                  "goal_time_tolerance": 2.5})"));
  ASSERT_TRUE(b.options.path_tolerance && b.options.goal_tolerance && b.options.goal_time_tolerance);
  EXPECT_EQ(b.options.path_tolerance->all, 0.3);
  EXPECT_EQ(b.options.path_tolerance->forJoint("wrist_3_joint"), 0.1);
  EXPECT_EQ(b.options.goal_tolerance->all, 0.005);
  EXPECT_EQ(*b.options.goal_time_tolerance, 2.5);
}

TEST(Tolerances, HostileToleranceOptionsAreRefused) {
  std::string many = "{\"all\": 0.1";
  for (int i = 0; i < 100; ++i) many += ", \"j" + std::to_string(i) + "\": 0.1";
  many += "}";
  for (const std::string& bad : std::vector<std::string>{
           R"({"path_tolerance": -0.1})",
           R"({"path_tolerance": "wide"})",
           R"({"path_tolerance": [0.1, 0.2]})",
           R"({"path_tolerance": {"elbow_joint": 0.1}})",  // no "all": the other joints would be unchecked
           R"({"path_tolerance": {"all": 0.1, "elbow_joint": -1}})",
           R"({"path_tolerance": {"all": 0.1, "elbow_joint": "x"}})",
           R"({"goal_tolerance": 1e400})",
           R"({"goal_time_tolerance": 0})",
           R"({"goal_time_tolerance": 3600})",
           R"({"time_scale": 1e300})",
           R"({"time_scale": 0})",
           R"({"start_delay": 1e9})",
           R"({"start_tolerance": 7})",
           std::string(R"({"path_tolerance": )") + many + "}",
           std::string(R"({"path_tolerance": {"all": 0.1, ")") + std::string(200, 'j') + R"(": 0.1}})",
       }) {
    EXPECT_THROW(parseDispatchRequest(request(bad)), InputError) << bad;
  }
}

TEST(Tolerances, PerJointNamesNotInThePlanAreRefusedNamingTheField) {
  Plan plan;
  plan.robots.push_back({});
  plan.robots.back().robot = "ur5e_0";
  plan.robots.back().joint_names = {"shoulder_pan_joint", "elbow_joint", "wrist_3_joint"};
  const auto check = [&](const std::string& options) {
    checkToleranceJoints(parseDispatchRequest(request(options)).options, plan);
  };
  EXPECT_NO_THROW(check(R"({"path_tolerance": {"all": 0.3, "wrist_3_joint": 0.1}, "goal_tolerance": 0.01})"));
  for (const auto& [bad, field] : std::vector<std::pair<std::string, std::string>>{
           {R"({"path_tolerance": {"all": 0.3, "wirst_3_joint": 0.1}})",
            "request.options.path_tolerance.wirst_3_joint"},
           {R"({"goal_tolerance": {"all": 0.01, "elbow_joint": 0.02, "Elbow_joint": 0.02}})",
            "request.options.goal_tolerance.Elbow_joint"},
       }) {
    try {
      check(bad);
      ADD_FAILURE() << "accepted " << bad;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(field + ": not a joint of the plan's arms (", 0), 0u) << what;
      EXPECT_NE(what.find("wrist_3_joint"), std::string::npos) << "the known joints listed: " << what;
    }
  }
}

TEST(Tolerances, TheAgentGetsItsGoalTolerancePerJoint) {
  TrajectoryCommand c;
  c.dispatch_id = "d1";
  c.trajectory.robot = "r";
  c.trajectory.joint_names = {"a", "b", "c"};
  c.trajectory.points = {{v3(0, 0, 0), v3(0, 0, 0), 0.0}};
  c.limits.goal_tolerance = v3(0.01, 0.02, 0.03);
  c.limits.goal_time_tolerance = 2.0;
  const TrajectoryCommand back = parseTrajectoryCommand(trajectoryCommandToJson(c));
  EXPECT_EQ(back.limits.goal_tolerance, v3(0.01, 0.02, 0.03));
  EXPECT_EQ(back.limits.goal_time_tolerance, 2.0);
  // Unset: the default for every joint.
  c.limits.goal_tolerance = JointVector();
  EXPECT_EQ(parseTrajectoryCommand(trajectoryCommandToJson(c)).limits.goalTolerance(3),
            JointVector::Constant(3, kDefaultGoalTolerance));
  // One number per joint, never negative.
  for (const char* bad : {"[0.1, -0.1, 0.1]", "[0.1, 0.1]", "-0.5", "\"x\""}) {
    nlohmann::json j = nlohmann::json::parse(trajectoryCommandToJson(c));
    j["limits"]["goal_tolerance"] = nlohmann::json::parse(bad);
    EXPECT_THROW(parseTrajectoryCommand(j.dump()), InputError) << bad;
  }
}

}  // namespace
}  // namespace dash::dispatch
