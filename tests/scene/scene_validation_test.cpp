// Every kind of bad scene input is an InputError whose message names the field path.
#include <gtest/gtest.h>

#include <functional>
#include <nlohmann/json.hpp>

#include "engine/scene/scene_json.h"
#include "tests/scene/scene_test_util.h"

namespace dash {
namespace {

using Json = nlohmann::ordered_json;

Json example() { return Json::parse(test::readFile(test::exampleScenePath())); }

/// Parses `text` and expects an InputError whose message contains `expected`.
void expectError(const std::string& text, const std::string& expected) {
  try {
    parseScene(text, test::library());
    ADD_FAILURE() << "no error; expected: " << expected;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << "message: " << e.what();
  }
}

void expectError(const std::function<void(Json&)>& edit, const std::string& expected) {
  Json j = example();
  edit(j);
  expectError(j.dump(), expected);
}

TEST(SceneValidation, TheExampleIsValid) { EXPECT_NO_THROW(parseScene(example().dump(), test::library())); }

TEST(SceneValidation, UnknownFormatAndBadJson) {
  expectError([](Json& j) { j["format"] = "dashbench.scene/2"; }, "format: unknown format \"dashbench.scene/2\"");
  expectError([](Json& j) { j.erase("format"); }, "format: missing field");
  expectError("{\"format\": ", "invalid JSON");
  expectError("[1, 2]", "scene: expected an object");
}

TEST(SceneValidation, UnknownModel) {
  expectError([](Json& j) { j["robots"][0]["model"] = "ur10"; }, "robots[0].model: unknown robot model \"ur10\"");
}

TEST(SceneValidation, DuplicateIds) {
  expectError([](Json& j) { j["objects"][0]["id"] = "table"; }, "objects[0].id: duplicate id \"table\" (also obstacles[0])");
  expectError([](Json& j) { j["robots"].push_back(j["robots"][0]); }, "robots[1].id: duplicate id \"ur5e_0\"");
  expectError([](Json& j) { j["obstacles"][0]["id"] = "ur5e_0"; }, "obstacles[0].id: duplicate id");
  expectError([](Json& j) { j["surfaces"].push_back(j["surfaces"][0]); }, "surfaces[1].id: duplicate surface id");
}

TEST(SceneValidation, NonFiniteNumbers) {
  // JSON has no NaN or infinity literal: both a NaN and an overflowing literal are rejected.
  std::string text = example().dump();
  const std::string needle = "-0.025";
  text.replace(text.find(needle), needle.size(), "1e999");
  expectError(text, "invalid JSON");
  std::string nan_text = example().dump();
  nan_text.replace(nan_text.find(needle), needle.size(), "NaN");
  expectError(nan_text, "invalid JSON");
}

TEST(SceneValidation, NonUnitQuaternion) {
  expectError([](Json& j) { j["robots"][0]["base"]["q"] = {0, 0, 0, 2}; }, "robots[0].base.q: quaternion is not unit length");
  expectError([](Json& j) { j["objects"][0]["goal"]["q"] = {0, 0, 0.1, 1}; }, "objects[0].goal.q: quaternion is not unit length");
  expectError([](Json& j) { j["obstacles"][0]["pose"]["q"] = {0, 0, 0, 0}; }, "obstacles[0].pose.q: quaternion is not unit length");
}

TEST(SceneValidation, SizesMustBePositive) {
  expectError([](Json& j) { j["obstacles"][0]["shape"]["size"][2] = 0.0; }, "obstacles[0].shape.size[2]: box size must be positive");
  expectError([](Json& j) { j["objects"][0]["shape"]["size"][0] = -0.04; }, "objects[0].shape.size[0]: box size must be positive");
  expectError([](Json& j) { j["objects"][0]["shape"]["type"] = "sphere"; }, "objects[0].shape.type: unknown shape type \"sphere\"");
}

TEST(SceneValidation, WrongArrayLengths) {
  expectError([](Json& j) { j["robots"][0]["home"].erase(5); }, "robots[0].home: expected 6 numbers, got 5");
  expectError([](Json& j) { j["objects"][0]["start"]["p"] = {0.1, 0.2}; }, "objects[0].start.p: expected 3 numbers, got 2");
  expectError([](Json& j) { j["robots"][0]["base"]["q"] = {0, 0, 1}; }, "robots[0].base.q: expected 4 numbers, got 3");
  expectError([](Json& j) { j["obstacles"][0]["shape"]["size"] = {1, 1}; }, "obstacles[0].shape.size: expected 3 numbers");
  expectError([](Json& j) { j["surfaces"][0]["polygon"][1] = {1, 2, 3}; }, "surfaces[0].polygon[1]: expected 2 numbers");
}

TEST(SceneValidation, WrongTypes) {
  expectError([](Json& j) { j["robots"][0]["home"][2] = "x"; }, "robots[0].home[2]: expected a number");
  expectError([](Json& j) { j["robots"] = Json::object(); }, "robots: expected an array");
  expectError([](Json& j) { j["objects"][0]["fixed"] = 1; }, "objects[0].fixed: expected true or false");
  expectError([](Json& j) { j["end_at_home"] = "yes"; }, "end_at_home: expected true or false");
}

TEST(SceneValidation, HomeOutsideLimits) {
  expectError([](Json& j) { j["robots"][0]["home"][2] = 3.5; }, "robots[0].home[2]: joint elbow_joint = 3.5 is outside its limits");
}

TEST(SceneValidation, MissingFields) {
  expectError([](Json& j) { j.erase("name"); }, "name: missing field");
  expectError([](Json& j) { j.erase("robots"); }, "robots: missing field");
  expectError([](Json& j) { j["objects"][0].erase("start"); }, "objects[0].start: missing field");
  expectError([](Json& j) { j["robots"][0]["base"].erase("q"); }, "robots[0].base.q: missing field");
  expectError([](Json& j) { j["robots"][0].erase("home"); }, "robots[0].home: missing field");
  expectError([](Json& j) { j["obstacles"][0].erase("shape"); }, "obstacles[0].shape: missing field");
  expectError([](Json& j) { j["surfaces"][0].erase("z"); }, "surfaces[0].z: missing field");
}

TEST(SceneValidation, OptionalFieldsMayBeOmitted) {
  Json j = example();
  j.erase("tasks");
  j["objects"][0].erase("goal");
  j["objects"][0].erase("fixed");
  const Scene scene = parseScene(j.dump(), test::library());
  EXPECT_TRUE(scene.tasks.empty());
  EXPECT_FALSE(scene.objects[0].X_WO_goal.has_value());
  EXPECT_FALSE(scene.objects[0].fixed);
  EXPECT_TRUE(scene.end_at_home);
}

TEST(SceneValidation, PolygonNeedsThreePoints) {
  expectError([](Json& j) { j["surfaces"][0]["polygon"] = {{0, 0}, {1, 0}}; }, "surfaces[0].polygon: a polygon needs at least 3 points, got 2");
  expectError([](Json& j) { j["surfaces"][0]["polygon"] = {{0, 0}, {1, 0}, {2, 0}}; }, "surfaces[0].polygon: polygon has zero area");
}

TEST(SceneValidation, TasksReferenceKnownObjects) {
  const Json task = Json::parse(R"({"type": "inspect", "target": "obj_0", "pose": {"p": [0.5, 0, 0.3], "q": [1, 0, 0, 0]},
                                   "requires_removed": "obj_0", "capability": "inspect"})");
  expectError([&](Json& j) { j["tasks"] = {task}; j["tasks"][0]["target"] = "container_9"; },
              "tasks[0].target: unknown object \"container_9\"");
  expectError([&](Json& j) { j["tasks"] = {task}; j["tasks"][0]["requires_removed"] = "lid_9"; },
              "tasks[0].requires_removed: unknown object \"lid_9\"");
  expectError([&](Json& j) { j["tasks"] = {task}; j["tasks"][0]["type"] = "weld"; }, "tasks[0].type: unknown task type \"weld\"");
  expectError([&](Json& j) { j["tasks"] = {task}; j["tasks"][0].erase("capability"); }, "tasks[0].capability: missing field");
  Json ok = example();
  ok["tasks"] = {task};
  EXPECT_NO_THROW(parseScene(ok.dump(), test::library()));
}

TEST(SceneValidation, GeneratorIsChecked) {
  expectError([](Json& j) { j["generator"] = {{"name", "sorting"}, {"params", {{"robots", {1, 2}}}}, {"seed", 1}}; },
              "generator.params.robots: expected a number or a string");
  expectError([](Json& j) { j["generator"] = {{"name", "sorting"}, {"params", Json::object()}, {"seed", -1}}; },
              "generator.seed: seed must not be negative");
  expectError([](Json& j) { j["generator"] = {{"name", "sorting"}, {"params", Json::object()}}; }, "generator.seed: missing field");
}

TEST(SceneValidation, SourceNamePrefixesErrors) {
  Json j = example();
  j["robots"][0]["model"] = "ur10";
  try {
    parseScene(j.dump(), test::library(), "my.json");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("my.json: robots[0].model", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace dash
