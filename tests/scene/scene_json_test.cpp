#include <gtest/gtest.h>

#include <cstdio>

#include "engine/scene/scene_json.h"
#include "tests/scene/scene_test_util.h"

namespace dash {
namespace {

using test::library;

void expectSamePose(const Pose& a, const Pose& b) {
  EXPECT_LT(translationDistance(a, b), 1e-12);
  EXPECT_LT(rotationDistance(a, b), 1e-9);
}

/// Field-by-field equality (poses to 1e-12 m, 1e-9 rad: quaternion -> matrix -> quaternion).
void expectSameScene(const Scene& a, const Scene& b) {
  EXPECT_EQ(a.name, b.name);
  ASSERT_EQ(a.generator.has_value(), b.generator.has_value());
  if (a.generator) {
    EXPECT_EQ(a.generator->name, b.generator->name);
    EXPECT_EQ(a.generator->params, b.generator->params);
    EXPECT_EQ(a.generator->seed, b.generator->seed);
  }
  ASSERT_EQ(a.robots.size(), b.robots.size());
  for (std::size_t i = 0; i < a.robots.size(); ++i) {
    EXPECT_EQ(a.robots[i].id, b.robots[i].id);
    EXPECT_EQ(a.robots[i].model_name, b.robots[i].model_name);
    EXPECT_EQ(a.robots[i].model, b.robots[i].model);
    expectSamePose(a.robots[i].X_WB, b.robots[i].X_WB);
    EXPECT_EQ(a.robots[i].home, b.robots[i].home);
    EXPECT_EQ(a.robots[i].capabilities, b.robots[i].capabilities);
  }
  ASSERT_EQ(a.obstacles.size(), b.obstacles.size());
  for (std::size_t i = 0; i < a.obstacles.size(); ++i) {
    EXPECT_EQ(a.obstacles[i].id, b.obstacles[i].id);
    EXPECT_EQ(a.obstacles[i].shape.size, b.obstacles[i].shape.size);
    expectSamePose(a.obstacles[i].X_WO, b.obstacles[i].X_WO);
  }
  ASSERT_EQ(a.surfaces.size(), b.surfaces.size());
  for (std::size_t i = 0; i < a.surfaces.size(); ++i) {
    EXPECT_EQ(a.surfaces[i].id, b.surfaces[i].id);
    EXPECT_EQ(a.surfaces[i].z, b.surfaces[i].z);
    EXPECT_EQ(a.surfaces[i].polygon, b.surfaces[i].polygon);
  }
  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (std::size_t i = 0; i < a.objects.size(); ++i) {
    EXPECT_EQ(a.objects[i].id, b.objects[i].id);
    EXPECT_EQ(a.objects[i].shape.size, b.objects[i].shape.size);
    expectSamePose(a.objects[i].X_WO_start, b.objects[i].X_WO_start);
    ASSERT_EQ(a.objects[i].X_WO_goal.has_value(), b.objects[i].X_WO_goal.has_value());
    if (a.objects[i].X_WO_goal) expectSamePose(*a.objects[i].X_WO_goal, *b.objects[i].X_WO_goal);
    EXPECT_EQ(a.objects[i].fixed, b.objects[i].fixed);
  }
  ASSERT_EQ(a.tasks.size(), b.tasks.size());
  for (std::size_t i = 0; i < a.tasks.size(); ++i) {
    EXPECT_EQ(a.tasks[i].target, b.tasks[i].target);
    EXPECT_EQ(a.tasks[i].target_object, b.tasks[i].target_object);
    expectSamePose(a.tasks[i].X_WT, b.tasks[i].X_WT);
    EXPECT_EQ(a.tasks[i].requires_removed, b.tasks[i].requires_removed);
    EXPECT_EQ(a.tasks[i].requires_removed_object, b.tasks[i].requires_removed_object);
    EXPECT_EQ(a.tasks[i].capability, b.tasks[i].capability);
  }
  EXPECT_EQ(a.end_at_home, b.end_at_home);
}

/// A scene that uses every field: generator, two models, fixed objects, a goal-less lid, a task.
const char* const kLabScene = R"({
 "format": "dashbench.scene/1",
 "name": "lab-test",
 "generator": {"name": "lab", "params": {"robots": 2, "spacing": 0.75, "layout": "row", "alpha": 1}, "seed": 17},
 "robots": [
  {"id": "ur5e_0", "model": "ur5e", "base": {"p": [0, 0, 0], "q": [0, 0, 0.7071067811865476, 0.7071067811865476]},
   "home": [0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0], "capabilities": ["grasp"]},
  {"id": "gantry_1", "model": "gantry3", "base": {"p": [0.5, -0.3, 0], "q": [0, 0, 0, 1]},
   "home": [0.1, 0.2, 0.0], "capabilities": ["grasp", "inspect"]}
 ],
 "obstacles": [
  {"id": "table", "shape": {"type": "box", "size": [3, 3, 0.05]}, "pose": {"p": [0, 0, -0.025], "q": [0, 0, 0, 1]}}
 ],
 "surfaces": [{"id": "table_top", "z": 0.0, "polygon": [[-1.5, -1.5], [1.5, -1.5], [1.5, 1.5], [-1.5, 1.5]]}],
 "objects": [
  {"id": "container_0", "shape": {"type": "box", "size": [0.1, 0.1, 0.08]},
   "start": {"p": [0.8, 0.0, 0.04], "q": [0, 0, 0, 1]}, "fixed": true},
  {"id": "lid_0", "shape": {"type": "box", "size": [0.1, 0.1, 0.01]},
   "start": {"p": [0.8, 0.0, 0.085], "q": [0, 0, 0, 1]}, "fixed": false},
  {"id": "obj_0", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]},
   "start": {"p": [0.5, 0.1, 0.02], "q": [0, 0, 0, 1]}, "goal": {"p": [-0.5, 0.1, 0.02], "q": [0, 0, 0.3826834323650898, 0.9238795325112867]}}
 ],
 "tasks": [{"type": "inspect", "target": "container_0", "pose": {"p": [0.8, 0.0, 0.3], "q": [1, 0, 0, 0]},
            "requires_removed": "lid_0", "capability": "inspect"}],
 "end_at_home": false
})";

TEST(SceneJson, LoadsTheContractExample) {
  const Scene scene = loadScene(test::exampleScenePath(), library());
  EXPECT_EQ(scene.name, "example-pick-place");
  ASSERT_EQ(scene.robots.size(), 1u);
  EXPECT_EQ(scene.robots[0].model_name, "ur5e");
  ASSERT_NE(scene.robots[0].model, nullptr);
  EXPECT_EQ(scene.robots[0].model->name, "ur5e");
  EXPECT_EQ(scene.robots[0].home.size(), 6);
  EXPECT_DOUBLE_EQ(scene.robots[0].home[1], -1.5708);
  EXPECT_TRUE(scene.robots[0].hasCapability("grasp"));
  ASSERT_EQ(scene.obstacles.size(), 1u);
  EXPECT_EQ(scene.obstacles[0].shape.size, Vec3(3.0, 3.0, 0.05));
  ASSERT_EQ(scene.surfaces.size(), 1u);
  EXPECT_EQ(scene.surfaces[0].polygon.size(), 4u);
  ASSERT_EQ(scene.objects.size(), 1u);
  ASSERT_TRUE(scene.objects[0].X_WO_goal.has_value());
  EXPECT_FALSE(scene.objects[0].fixed);
  EXPECT_TRUE(scene.tasks.empty());
  EXPECT_TRUE(scene.end_at_home);
  EXPECT_FALSE(scene.generator.has_value());
  EXPECT_EQ(scene.robotIndex("ur5e_0"), 0);
  EXPECT_EQ(scene.robotIndex("nobody"), -1);
  EXPECT_EQ(scene.objectIndex("obj_0"), 0);
  EXPECT_EQ(scene.objectIndex("table"), -1);
  EXPECT_EQ(scene.obstacleIndex("table"), 0);
}

TEST(SceneJson, ParsesEveryField) {
  const Scene scene = parseScene(kLabScene, library());
  ASSERT_TRUE(scene.generator.has_value());
  EXPECT_EQ(scene.generator->seed, 17u);
  ASSERT_EQ(scene.generator->params.size(), 4u);
  EXPECT_EQ(scene.generator->params[0].first, "robots");  // file order, not sorted
  EXPECT_EQ(std::get<double>(scene.generator->params[0].second), 2.0);
  EXPECT_EQ(scene.generator->params[2].first, "layout");
  EXPECT_EQ(std::get<std::string>(scene.generator->params[2].second), "row");
  EXPECT_EQ(scene.robots[1].model->name, "gantry3");
  EXPECT_TRUE(scene.objects[0].fixed);
  EXPECT_FALSE(scene.objects[1].X_WO_goal.has_value());
  ASSERT_EQ(scene.tasks.size(), 1u);
  EXPECT_EQ(scene.tasks[0].target_object, 0);
  EXPECT_EQ(scene.tasks[0].requires_removed_object, 1);
  EXPECT_EQ(scene.tasks[0].capability, "inspect");
  EXPECT_FALSE(scene.end_at_home);
  EXPECT_EQ(scene.library, library());
}

TEST(SceneJson, RoundTripKeepsEveryField) {
  for (const std::string& text : {test::readFile(test::exampleScenePath()), std::string(kLabScene)}) {
    const Scene a = parseScene(text, library());
    const std::string saved = sceneToJson(a);
    const Scene b = parseScene(saved, library());
    expectSameScene(a, b);
    // Deterministic: the same scene gives the same bytes. (Saving the reloaded scene may differ in the
    // last digit of a quaternion: quaternion -> rotation matrix -> quaternion is not bit-exact.)
    EXPECT_EQ(saved, sceneToJson(a));
    EXPECT_EQ(saved, sceneToJson(parseScene(text, library())));
  }
}

TEST(SceneJson, SaveThenLoadFromDisk) {
  const Scene a = parseScene(kLabScene, library());
  const std::string path = testing::TempDir() + "/dash_scene_roundtrip.json";
  saveScene(a, path);
  const Scene b = loadScene(path, library());
  expectSameScene(a, b);
  std::remove(path.c_str());
}

TEST(SceneJson, MissingFileIsInputError) {
  EXPECT_THROW(loadScene("/nonexistent/scene.json", library()), InputError);
  EXPECT_THROW(saveScene(parseScene(kLabScene, library()), "/nonexistent/dir/scene.json"), InputError);
}

}  // namespace
}  // namespace dash
