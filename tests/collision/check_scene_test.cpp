// `dashbench check-scene`: the contract example passes; broken variants fail with exit 1 (problems) or
// 2 (invalid input). The engine function is tested directly for the wording of each problem.
#include <gtest/gtest.h>


#include <cstdio>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/collision/scene_check.h"
#include "tests/collision/collision_test_util.h"
#include "tests/common/cli_run.h"

namespace dash {
namespace {

using Json = nlohmann::ordered_json;

Json example() {
  std::ifstream in(test::exampleScenePath());
  return Json::parse(in);
}

using CliResult = test::CliRun;

CliResult runCheckScene(const std::string& arguments) { return test::runDashbench("check-scene " + arguments); }

std::string writeScene(const Json& scene, const std::string& name) {
  const std::string path = testing::TempDir() + "/dash_check_scene_" + name + ".json";
  std::ofstream(path) << scene.dump(1);
  return path;
}

/// Problems found in the example after `edit`.
std::vector<std::string> problemsAfter(const std::function<void(Json&)>& edit) {
  Json j = example();
  edit(j);
  const Scene scene = parseScene(j.dump(), test::library());
  return findSceneProblems(scene);
}

bool anyContains(const std::vector<std::string>& problems, const std::string& text) {
  for (const auto& p : problems) {
    if (p.find(text) != std::string::npos) return true;
  }
  return false;
}

std::string joined(const std::vector<std::string>& problems) {
  std::ostringstream out;
  for (const auto& p : problems) out << p << "\n";
  return out.str();
}

TEST(CheckScene, ExamplePasses) {
  const Scene scene = test::exampleScene();
  EXPECT_TRUE(findSceneProblems(scene).empty()) << joined(findSceneProblems(scene));
  const CliResult r = runCheckScene(test::exampleScenePath());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("ok"), std::string::npos) << r.output;
}

TEST(CheckScene, FloatingObject) {
  const auto problems = problemsAfter([](Json& j) { j["objects"][0]["start"]["p"][2] = 0.1; });
  EXPECT_TRUE(anyContains(problems, "object obj_0 does not rest on a surface or another object at its start")) << joined(problems);
  const auto goal = problemsAfter([](Json& j) { j["objects"][0]["goal"]["p"] = {1.6, 0.0, 0.02}; });  // off the table's polygon
  EXPECT_TRUE(anyContains(goal, "object obj_0 does not rest on a surface or another object at its goal")) << joined(goal);
}

TEST(CheckScene, RobotHomeInAnObstacle) {
  const auto problems = problemsAfter([](Json& j) {
    j["obstacles"].push_back({{"id", "pillar"}, {"shape", {{"type", "box"}, {"size", {0.1, 0.1, 1.0}}}},
                              {"pose", {{"p", {0.0, 0.0, 0.5}}, {"q", {0, 0, 0, 1}}}}});
  });
  EXPECT_TRUE(anyContains(problems, "robot ur5e_0 at home collides")) << joined(problems);
  EXPECT_TRUE(anyContains(problems, "obstacle pillar")) << joined(problems);
}

TEST(CheckScene, ObjectsCollidingAtStartOrGoal) {
  const auto start = problemsAfter([](Json& j) {
    Json second = j["objects"][0];
    second["id"] = "obj_1";
    second["start"]["p"] = {-0.49, -0.2, 0.02};
    second.erase("goal");
    j["objects"].push_back(second);
  });
  EXPECT_TRUE(anyContains(start, "object obj_0 at its start collides: object obj_0 vs object obj_1")) << joined(start);
  const auto goal = problemsAfter([](Json& j) {
    j["obstacles"].push_back({{"id", "block"}, {"shape", {{"type", "box"}, {"size", {0.1, 0.1, 0.1}}}},
                              {"pose", {{"p", {-0.5, 0.2, 0.05}}, {"q", {0, 0, 0, 1}}}}});
  });
  EXPECT_TRUE(anyContains(goal, "object obj_0 at its goal collides: object obj_0 vs obstacle block")) << joined(goal);
}

TEST(CheckScene, ObjectOutOfReach) {
  const auto problems = problemsAfter([](Json& j) { j["objects"][0]["start"]["p"] = {1.4, 1.4, 0.02}; });
  EXPECT_TRUE(anyContains(problems, "object obj_0 cannot be grasped at its start")) << joined(problems);
  EXPECT_FALSE(anyContains(problems, "at its goal")) << joined(problems);
  // Without the grasp capability nobody can grasp it anywhere.
  const auto no_grasp = problemsAfter([](Json& j) { j["robots"][0]["capabilities"] = Json::array(); });
  EXPECT_TRUE(anyContains(no_grasp, "cannot be grasped at its start")) << joined(no_grasp);
  EXPECT_TRUE(anyContains(no_grasp, "cannot be grasped at its goal")) << joined(no_grasp);
}

TEST(CheckScene, EveryFamilyExamplePasses) {
  // The shelf families' rear slots are blocked by the objects in front of them at the goal (and
  // stocking's middle items at the start) on purpose: check-scene must accept that.
  for (const char* family : {"sorting", "wall", "shelf-wall", "stocking", "lab"}) {
    const std::string path = std::string(DASHBENCH_DATA_DIR) + "/scenes/" + family + ".json";
    const CliResult r = runCheckScene(path);
    EXPECT_EQ(r.exit_code, 0) << family << "\n" << r.output;
    EXPECT_NE(r.output.find(": ok ("), std::string::npos) << family << "\n" << r.output;
  }
}

TEST(CheckScene, CliExitCodes) {
  Json floating = example();
  floating["objects"][0]["start"]["p"][2] = 0.1;
  const CliResult problems = runCheckScene(writeScene(floating, "floating"));
  EXPECT_EQ(problems.exit_code, 1) << problems.output;
  EXPECT_NE(problems.output.find("does not rest"), std::string::npos) << problems.output;

  Json bad_quaternion = example();
  bad_quaternion["robots"][0]["base"]["q"] = {0, 0, 0, 2};
  const CliResult invalid = runCheckScene(writeScene(bad_quaternion, "bad_quaternion"));
  EXPECT_EQ(invalid.exit_code, 2) << invalid.output;
  EXPECT_NE(invalid.output.find("robots[0].base.q: quaternion is not unit length"), std::string::npos) << invalid.output;

  EXPECT_EQ(runCheckScene("/nonexistent/scene.json").exit_code, 2);
  EXPECT_EQ(runCheckScene("").exit_code, 2);
  EXPECT_EQ(runCheckScene("--help").exit_code, 0);
}

}  // namespace
}  // namespace dash
