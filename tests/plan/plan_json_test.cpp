#include <gtest/gtest.h>

#include "engine/core/check.h"
#include "engine/plan/plan_json.h"
#include "plan_test_util.h"

namespace dash {
namespace {

using test::examplePlan;
using test::examplePlanPath;
using test::readFile;

std::string exampleText() { return readFile(examplePlanPath()); }

/// The example text with the first occurrence of `from` replaced by `to` (which must exist).
std::string edited(const std::string& from, const std::string& to) {
  std::string text = exampleText();
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

std::string parseError(const std::string& text) {
  try {
    parsePlan(text, "plan.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(PlanJson, ParsesTheExample) {
  const Plan plan = examplePlan();
  EXPECT_EQ(plan.format, "dashbench.plan/1");
  EXPECT_EQ(plan.scene, "example-pick-place");
  EXPECT_EQ(plan.planner, "hand-made");
  EXPECT_EQ(plan.status, "solved");
  EXPECT_DOUBLE_EQ(plan.makespan, 3.38);
  ASSERT_EQ(plan.robots.size(), 1u);
  const RobotTrajectory& r = plan.robots.front();
  EXPECT_EQ(r.robot, "ur5e_0");
  EXPECT_EQ(r.joint_names.size(), 6u);
  EXPECT_EQ(r.joint_names.front(), "shoulder_pan_joint");
  ASSERT_EQ(r.points.size(), 12u);
  EXPECT_DOUBLE_EQ(r.points[1].t, 1.09);
  EXPECT_DOUBLE_EQ(r.points[1].q[0], 0.13037434382487367);
  ASSERT_EQ(plan.events.size(), 2u);
  EXPECT_EQ(plan.events[0].type, PlanEvent::Type::kGrasp);
  EXPECT_EQ(plan.events[0].object, "obj_0");
  EXPECT_DOUBLE_EQ(plan.events[0].t, 1.39);
  EXPECT_NEAR(rotationDistance(plan.events[0].X_TO, makePose(Vec3::Zero(), Quat(0, 1, 0, 0))), 0.0, 1e-12);
  EXPECT_EQ(plan.events[1].type, PlanEvent::Type::kRelease);
  EXPECT_DOUBLE_EQ(plan.events[1].t, 2.48);
}

TEST(PlanJson, RoundTripKeepsEveryValue) {
  const Plan a = examplePlan();
  const std::string text = planToJson(a);
  const Plan b = parsePlan(text);
  EXPECT_EQ(planToJson(b), text);  // deterministic and stable
  EXPECT_EQ(b.scene, a.scene);
  EXPECT_EQ(b.makespan, a.makespan);
  ASSERT_EQ(b.robots.size(), a.robots.size());
  EXPECT_EQ(b.robots[0].joint_names, a.robots[0].joint_names);
  ASSERT_EQ(b.robots[0].points.size(), a.robots[0].points.size());
  for (std::size_t k = 0; k < a.robots[0].points.size(); ++k) {
    EXPECT_EQ(b.robots[0].points[k].t, a.robots[0].points[k].t);
    EXPECT_EQ(b.robots[0].points[k].q, a.robots[0].points[k].q);  // doubles print exactly
  }
  ASSERT_EQ(b.events.size(), a.events.size());
  for (std::size_t k = 0; k < a.events.size(); ++k) {
    EXPECT_EQ(b.events[k].type, a.events[k].type);
    EXPECT_EQ(b.events[k].t, a.events[k].t);
    EXPECT_EQ(b.events[k].robot, a.events[k].robot);
    EXPECT_EQ(b.events[k].object, a.events[k].object);
    EXPECT_TRUE(b.events[k].X_TO.isApprox(a.events[k].X_TO, 1e-12));
  }
}

TEST(PlanJson, WritesFieldsInContractOrder) {
  const std::string text = planToJson(examplePlan());
  const auto pos = [&](const std::string& key) { return text.find("\"" + key + "\""); };
  EXPECT_LT(pos("format"), pos("scene"));
  EXPECT_LT(pos("scene"), pos("planner"));
  EXPECT_LT(pos("planner"), pos("status"));
  EXPECT_LT(pos("status"), pos("makespan"));
  EXPECT_LT(pos("makespan"), pos("robots"));
  EXPECT_LT(pos("robots"), pos("events"));
  EXPECT_EQ(text.back(), '\n');
}

TEST(PlanJson, KeepsRobotOrderAndInspectEvents) {
  Plan plan;
  plan.scene = "s";
  plan.planner = "p";
  plan.robots.push_back({"zeta", {"j"}, {{0.0, test::joints({1.0})}}});
  plan.robots.push_back({"alpha", {"j"}, {{0.0, test::joints({2.0})}}});
  plan.events.push_back({PlanEvent::Type::kInspect, 0.5, "zeta", "", Pose::Identity(), 3});
  const Plan back = parsePlan(planToJson(plan));
  ASSERT_EQ(back.robots.size(), 2u);
  EXPECT_EQ(back.robots[0].robot, "zeta");
  EXPECT_EQ(back.robots[1].robot, "alpha");
  ASSERT_EQ(back.events.size(), 1u);
  EXPECT_EQ(back.events[0].type, PlanEvent::Type::kInspect);
  EXPECT_EQ(back.events[0].task, 3);
  EXPECT_TRUE(back.events[0].object.empty());
}

TEST(PlanJson, SaveAndLoad) {
  const std::string path = ::testing::TempDir() + "plan_json_test_plan.json";
  const Plan plan = examplePlan();
  savePlan(plan, path);
  EXPECT_EQ(planToJson(loadPlan(path)), planToJson(plan));
  EXPECT_THROW(loadPlan(path + ".missing"), InputError);
}

TEST(PlanJson, ErrorsNameTheField) {
  const std::string missing = parseError(edited("\"makespan\": 3.38,", ""));
  EXPECT_NE(missing.find("plan.json: makespan: missing field"), std::string::npos) << missing;
  EXPECT_NE(parseError(edited("dashbench.plan/1", "dashbench.plan/9")).find("format: unknown format"), std::string::npos);
  EXPECT_NE(parseError(edited("\"type\": \"grasp\"", "\"type\": \"poke\"")).find("events[0].type: unknown event type"),
            std::string::npos);
  EXPECT_NE(parseError(edited("\"t\": 1.09", "\"t\": -1.09")).find("robots.ur5e_0.points[1].t: time must not be negative"),
            std::string::npos);
  EXPECT_NE(parseError(edited("\"t\": 1.09,\n     \"q\": [\n      0.13037434382487367,",
                              "\"t\": 1.09,\n     \"q\": ["))
                .find("robots.ur5e_0.points[1].q: expected 6 numbers, got 5"),
            std::string::npos);
  EXPECT_NE(parseError(edited("\"q\": [\n     1.0,", "\"q\": [\n     2.0,")).find("events[0].X_TO.q: quaternion is not unit length"),
            std::string::npos);
  EXPECT_NE(parseError(edited("\"robot\": \"ur5e_0\",\n   \"object\": \"obj_0\",\n   \"X_TO\"", "\"robot\": \"ur5e_0\",\n   \"X_TO\""))
                .find("events[0].object: missing field"),
            std::string::npos);
  EXPECT_NE(parseError("{").find("invalid JSON"), std::string::npos);
  EXPECT_NE(parseError("[]").find("plan: expected an object"), std::string::npos);
}

TEST(Plan, PositionAtInterpolatesAndHolds) {
  const RobotTrajectory traj{"r", {"a", "b"}, {{0.0, test::joints({0.0, 1.0})}, {2.0, test::joints({1.0, 3.0})}}};
  EXPECT_TRUE(traj.positionAt(0.0).isApprox(test::joints({0.0, 1.0})));
  EXPECT_TRUE(traj.positionAt(0.5).isApprox(test::joints({0.25, 1.5})));
  EXPECT_TRUE(traj.positionAt(2.0).isApprox(test::joints({1.0, 3.0})));
  EXPECT_TRUE(traj.positionAt(10.0).isApprox(test::joints({1.0, 3.0})));  // holds still after the last point
  EXPECT_THROW(traj.positionAt(-0.1), InputError);
  EXPECT_THROW(RobotTrajectory{}.positionAt(0.0), InputError);
  EXPECT_DOUBLE_EQ(traj.endTime(), 2.0);
}

TEST(Plan, SortRobotsFollowsTheScene) {
  const Scene scene = test::twoArmScene();
  Plan plan = test::twoArmPlan(scene, 0.0);
  std::swap(plan.robots[0], plan.robots[1]);
  plan.robots.push_back({"stranger", {}, {}});
  std::swap(plan.robots[0], plan.robots[2]);
  plan.sortRobots(scene);
  EXPECT_EQ(plan.robots[0].robot, "ur5e_0");
  EXPECT_EQ(plan.robots[1].robot, "ur5e_1");
  EXPECT_EQ(plan.robots[2].robot, "stranger");
  EXPECT_NE(plan.findRobot("ur5e_1"), nullptr);
  EXPECT_EQ(plan.findRobot("nobody"), nullptr);
  EXPECT_DOUBLE_EQ(plan.lastTime(), 2.0);
}

}  // namespace
}  // namespace dash
