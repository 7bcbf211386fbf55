// Loader of dashbench.robot/1 files: the shipped models load, malformed variants are rejected with
// an InputError that names the offending field.
#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "engine/core/paths.h"
#include "engine/robots/robot_model.h"

namespace dash {
namespace {

using nlohmann::json;

json readModelJson(const std::string& name) {
  std::ifstream in(dataDirectory() + "/robots/" + name + ".json");
  EXPECT_TRUE(in.good()) << name;
  return json::parse(in);
}

TEST(RobotLibrary, LoadsBothShippedModels) {
  auto lib = RobotLibrary::loadDefault();
  ASSERT_NE(lib->find("ur5e"), nullptr);
  ASSERT_NE(lib->find("gantry3"), nullptr);
  EXPECT_EQ(lib->find("nope"), nullptr);
  EXPECT_THROW(lib->get("nope"), InputError);
  EXPECT_EQ(lib->names().size(), 2u);
}

TEST(RobotModel, Ur5eFields) {
  const auto lib = RobotLibrary::loadDefault();
  const RobotModel& m = lib->get("ur5e");
  EXPECT_EQ(m.kinematics, KinematicsKind::kUrDh);
  EXPECT_EQ(m.dof(), 6);
  EXPECT_EQ(m.joint_names[0], "shoulder_pan_joint");
  EXPECT_DOUBLE_EQ(m.dh.a[1], -0.425);
  EXPECT_DOUBLE_EQ(m.dh.d[5], 0.0996);
  EXPECT_EQ(m.dh.cos_alpha[0], 0.0);  // snapped
  EXPECT_EQ(m.dh.sin_alpha[4], -1.0);
  EXPECT_NEAR(m.dh.X_FT.translation().z(), 0.157, 1e-15);
  EXPECT_EQ(m.bodies.size(), 12u);
  EXPECT_EQ(m.self_collision_pairs.size(), 29u);
  EXPECT_DOUBLE_EQ(m.limits.position_max[2], M_PI);
  EXPECT_DOUBLE_EQ(m.limits.position_min[0], -2 * M_PI);
  for (const auto& b : m.bodies) {
    const bool gripper = b.name == "gripper_body" || b.name == "finger_left" || b.name == "finger_right";
    EXPECT_EQ(b.is_gripper, gripper) << b.name;
  }
  const CollisionBody& finger = m.bodies[static_cast<std::size_t>(m.bodyIndex("finger_left"))];
  EXPECT_EQ(finger.kind, CollisionBody::Kind::kBox);
  EXPECT_EQ(finger.frame, 6);
  EXPECT_DOUBLE_EQ(finger.box_center.x(), 0.0305);
  EXPECT_DOUBLE_EQ(finger.box_half_extents.z(), 0.025);
  const CollisionBody& upper = m.bodies[static_cast<std::size_t>(m.bodyIndex("upper_arm"))];
  EXPECT_EQ(upper.kind, CollisionBody::Kind::kCapsule);
  EXPECT_EQ(upper.frame, 2);
  EXPECT_DOUBLE_EQ(upper.capsule.a.x(), 0.425);
  EXPECT_DOUBLE_EQ(upper.capsule.radius, 0.06);
  EXPECT_EQ(m.bodyIndex("nope"), -1);
  const auto [i, j] = m.self_collision_pairs.front();
  EXPECT_EQ(m.bodies[static_cast<std::size_t>(i)].name, "forearm");
  EXPECT_EQ(m.bodies[static_cast<std::size_t>(j)].name, "base");
}

TEST(RobotModel, GantryFields) {
  const auto lib = RobotLibrary::loadDefault();
  const RobotModel& m = lib->get("gantry3");
  EXPECT_EQ(m.kinematics, KinematicsKind::kGantry);
  EXPECT_EQ(m.dof(), 3);
  EXPECT_DOUBLE_EQ(m.gantry.beam_height, 0.6);
  EXPECT_DOUBLE_EQ(m.gantry.ram_to_tcp, 0.2);
  ASSERT_EQ(m.bodies.size(), 4u);
  const CollisionBody& bridge = m.bodies[0];
  EXPECT_EQ(bridge.kind, CollisionBody::Kind::kBox);
  EXPECT_TRUE(bridge.moves[0]);
  EXPECT_FALSE(bridge.moves[1]);
  EXPECT_TRUE(bridge.box_center.isZero());
  EXPECT_TRUE(bridge.gantry_base_center.isApprox(Vec3(0.0, 0.30, 0.64)));
  EXPECT_FALSE(bridge.is_gripper);
  EXPECT_FALSE(m.bodies[1].is_gripper);  // carriage
  EXPECT_TRUE(m.bodies[3].is_gripper);   // tool: rigid with the TCP
  EXPECT_TRUE(m.self_collision_pairs.empty());
}

TEST(RobotModel, WithinLimits) {
  const auto lib = RobotLibrary::loadDefault();
  const RobotModel& m = lib->get("ur5e");
  JointVector q = JointVector::Zero(6);
  EXPECT_TRUE(m.withinLimits(q));
  q[2] = M_PI + 1e-10;
  EXPECT_TRUE(m.withinLimits(q));
  q[2] = M_PI + 1e-6;
  EXPECT_FALSE(m.withinLimits(q));
  q[2] = std::nan("");
  EXPECT_FALSE(m.withinLimits(q));
  EXPECT_FALSE(m.withinLimits(JointVector::Zero(3)));
}

// Applies `edit` to a shipped model and expects the loader to reject it with `field` in the message.
void expectRejected(const std::string& model, const std::function<void(json&)>& edit, const std::string& field) {
  json doc = readModelJson(model);
  edit(doc);
  try {
    parseRobotModel(doc.dump(), "bad.json");
    ADD_FAILURE() << "accepted a model with a bad " << field;
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(field), std::string::npos) << "message '" << msg << "' does not name " << field;
    EXPECT_NE(msg.find("bad.json"), std::string::npos) << msg;
  }
}

TEST(RobotModelLoader, ShippedModelsRoundTripThroughParse) {
  for (const char* name : {"ur5e", "gantry3"}) {
    EXPECT_NO_THROW(parseRobotModel(readModelJson(name).dump(), name));
  }
}

TEST(RobotModelLoader, RejectsMalformedUr5e) {
  const double inf = std::numeric_limits<double>::infinity();
  expectRejected("ur5e", [](json& j) { j["format"] = "dashbench.robot/2"; }, "format");
  expectRejected("ur5e", [](json& j) { j.erase("format"); }, "format");
  expectRejected("ur5e", [](json& j) { j.erase("model"); }, "model");
  expectRejected("ur5e", [](json& j) { j["model"] = 5; }, "model");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["a"].erase(5); }, "kinematics.a");
  expectRejected("ur5e", [](json& j) { j["kinematics"].erase("d"); }, "kinematics.d");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["d"][2] = "0.0"; }, "kinematics.d[2]");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["alpha"][1] = 0.3; }, "kinematics.alpha[1]");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["tcp_in_flange"]["q"] = {0, 0, 0, 2}; },
                 "kinematics.tcp_in_flange.q");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["tcp_in_flange"].erase("p"); },
                 "kinematics.tcp_in_flange.p");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["joint_names"].erase(0); }, "kinematics.joint_names");
  expectRejected("ur5e", [](json& j) { j["kinematics"]["joint_names"][1] = "shoulder_pan_joint"; },
                 "kinematics.joint_names[1]");
  // JSON text has no NaN/Infinity; an infinite value can only come through the library, as here.
  expectRejected("ur5e", [&](json& j) { j["limits"]["position_max"][3] = inf; }, "limits.position_max");
  expectRejected("ur5e", [](json& j) { j["limits"]["velocity_max"] = {1, 2, 3}; }, "limits.velocity_max");
  expectRejected("ur5e", [](json& j) { j["limits"]["velocity_max"][0] = 0.0; }, "limits.velocity_max[0]");
  expectRejected("ur5e", [](json& j) { j["limits"]["position_min"][0] = 7.0; }, "limits.position_min[0]");
  expectRejected("ur5e", [](json& j) { j["limits"]["position_min"][0] = true; }, "limits.position_min[0]");
  expectRejected("ur5e", [](json& j) { j.erase("limits"); }, "limits");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][3]["frame"] = 7; }, "collision.bodies[3].frame");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][3]["frame"] = 1.5; }, "collision.bodies[3].frame");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][2].erase("frame"); }, "collision.bodies[2].frame");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][2]["capsule"].erase("radius"); },
                 "collision.bodies[2].capsule.radius");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][2]["capsule"]["radius"] = -0.1; },
                 "collision.bodies[2].capsule.radius");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][2]["capsule"]["a"] = {0, 0}; },
                 "collision.bodies[2].capsule.a");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][10]["box"]["half_extents"][1] = 0; },
                 "collision.bodies[10].box.half_extents");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][1]["name"] = "base"; }, "collision.bodies[1].name");
  expectRejected("ur5e", [](json& j) { j["collision"]["bodies"][1]["box"] = j["collision"]["bodies"][10]["box"]; },
                 "collision.bodies[1]");
  expectRejected("ur5e", [](json& j) { j["collision"]["self_collision_pairs"][4][1] = "elbow_typo"; },
                 "collision.self_collision_pairs[4][1]");
  expectRejected("ur5e", [](json& j) { j["collision"]["self_collision_pairs"][0] = {"base"}; },
                 "collision.self_collision_pairs[0]");
  expectRejected("ur5e", [](json& j) { j["collision"].erase("self_collision_pairs"); },
                 "collision.self_collision_pairs");
}

TEST(RobotModelLoader, RejectsMalformedGantry) {
  expectRejected("gantry3", [](json& j) { j["kinematics"].erase("beam_height"); }, "kinematics.beam_height");
  expectRejected("gantry3", [](json& j) { j["kinematics"]["ram_to_tcp"] = nullptr; }, "kinematics.ram_to_tcp");
  expectRejected("gantry3", [](json& j) { j["collision"]["bodies"][0]["moves"] = {"w"}; },
                 "collision.bodies[0].moves[0]");
  expectRejected("gantry3", [](json& j) { j["collision"]["bodies"][0].erase("moves"); }, "collision.bodies[0].moves");
  expectRejected("gantry3", [](json& j) { j["collision"]["bodies"][1]["frame"] = 1; }, "collision.bodies[1].frame");
  expectRejected("gantry3", [](json& j) { j["limits"]["position_max"] = {1, 2}; }, "limits.position_max");
  expectRejected("gantry3", [](json& j) { j["kinematics"]["joint_names"].push_back("w"); }, "kinematics.joint_names");
}

TEST(RobotModelLoader, RejectsTextThatIsNotJson) {
  EXPECT_THROW(parseRobotModel("{\"format\": ", "x.json"), InputError);
  EXPECT_THROW(parseRobotModel("[1, 2]", "x.json"), InputError);
  EXPECT_THROW(parseRobotModel("{\"format\": \"dashbench.robot/1\", \"a\": NaN}", "x.json"), InputError);
  EXPECT_THROW(loadRobotModel("/nonexistent/robot.json"), InputError);
  EXPECT_THROW(RobotLibrary::loadDirectory("/nonexistent"), InputError);
}

TEST(RobotModelLoader, GripperFlagOverride) {
  json doc = readModelJson("ur5e");
  doc["collision"]["bodies"][9]["gripper"] = false;
  doc["collision"]["bodies"][8]["gripper"] = true;
  const RobotModel m = parseRobotModel(doc.dump(), "x.json");
  EXPECT_FALSE(m.bodies[9].is_gripper);
  EXPECT_TRUE(m.bodies[8].is_gripper);
  doc["collision"]["bodies"][8]["gripper"] = "yes";
  EXPECT_THROW(parseRobotModel(doc.dump(), "x.json"), InputError);
}

}  // namespace
}  // namespace dash
