// The grasp rule of check-scene: an object must be graspable at its start and goal among obstacles and
// fixed objects only. A one-cubby shelf (the geometry of data/scenes/shelf-wall.json, shelf_0 column 0)
// whose rear slot is blocked by the cube that goes in front of it passes; the same slot blocked by an
// obstacle or a fixed object fails. The other checks keep counting movable objects.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "engine/collision/collision_queries.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/collision/scene_check.h"
#include "tests/collision/collision_test_util.h"

namespace dash {
namespace {

using Kind = SceneProblem::Kind;
using Moment = SceneProblem::Moment;

constexpr double kHalfPi = 1.5707963267948966;
constexpr double kCube = 0.04;

// The cubby opens towards -y, where the robot stands; both slots share x.
constexpr double kSlotX = -0.095;
const Vec3 kFrontSlot(kSlotX, -0.11, 0.17);  // on a 3 cm pedestal on the cubby floor at 0.12
const Vec3 kRearSlot(kSlotX, -0.05, 0.20);   // on a 6 cm pedestal
const Vec3 kFrontTable(0.57, -0.76, 0.02);
const Vec3 kRearTable(0.57, -0.84, 0.02);

Pose shelfPose(const Vec3& p) { return test::yawPose(p.x(), p.y(), p.z(), -kHalfPi); }

void addRectSurface(Scene& s, const std::string& id, double z, double x0, double y0, double x1, double y1) {
  s.surfaces.push_back(SceneSurface{.id = id, .z = z, .polygon = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}});
}

/// One UR5e in front of one two-slot cubby, with the back wall behind it, and no objects.
Scene cubbyScene() {
  Scene s = test::emptyScene("cubby");
  test::addUr(s, "ur5e_0", test::yawPose(0.0, -0.6, 0.0, kHalfPi));
  test::addTable(s);
  test::addObstacle(s, "divider", Vec3(0.59, 0.02, 1.5), makePose(Vec3(0.0, 0.0, 0.75)));
  test::addObstacle(s, "shelf_base", Vec3(0.14, 0.39, 0.12), shelfPose(Vec3(0.0, -0.08, 0.06)));
  test::addObstacle(s, "shelf_board", Vec3(0.14, 0.39, 0.01), shelfPose(Vec3(0.0, -0.08, 0.26)));
  test::addObstacle(s, "shelf_panel_0", Vec3(0.14, 0.01, 0.135), shelfPose(Vec3(-0.19, -0.08, 0.1875)));
  test::addObstacle(s, "shelf_panel_1", Vec3(0.14, 0.01, 0.135), shelfPose(Vec3(0.0, -0.08, 0.1875)));
  test::addObstacle(s, "pedestal_front", Vec3(0.03, 0.03, 0.03), shelfPose(Vec3(kSlotX, -0.11, 0.135)));
  test::addObstacle(s, "pedestal_rear", Vec3(0.03, 0.03, 0.06), shelfPose(Vec3(kSlotX, -0.05, 0.15)));
  addRectSurface(s, "slot_front", 0.15, kSlotX - 0.025, -0.135, kSlotX + 0.025, -0.085);
  addRectSurface(s, "slot_rear", 0.18, kSlotX - 0.025, -0.075, kSlotX + 0.025, -0.025);
  return s;
}

void addMovable(Scene& s, const std::string& id, const Vec3& start, const Vec3& goal) {
  test::addCube(s, id, kCube, shelfPose(start));
  s.objects.back().X_WO_goal = shelfPose(goal);
}

/// Both cubes go from the table into the cubby: the rear one must go in first.
Scene stockedAtGoal() {
  Scene s = cubbyScene();
  addMovable(s, "rear", kRearTable, kRearSlot);
  addMovable(s, "front", kFrontTable, kFrontSlot);
  return s;
}

/// True if the robot can hold object j at X_WO without a collision among the objects of `layout`.
bool anyFreeGrasp(const Scene& scene, int j, const Pose& X_WO, const ObjectLayout& layout) {
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const SceneRobot& robot = scene.robots[0];
  for (const GraspCandidate& c : graspCandidates(*robot.model, robot.X_WB, scene.objects[static_cast<std::size_t>(j)].shape, X_WO)) {
    for (const JointVector& q : inverseKinematics(*robot.model, robot.X_WB, c.X_WT)) {
      if (!robotInCollision(world, context, {.robot = 0, .q = q, .held = {.object = j, .X_TO = c.X_TO}}, layout)) {
        return true;
      }
    }
  }
  return false;
}

std::string joined(const std::vector<SceneProblem>& problems) {
  std::ostringstream out;
  for (const auto& p : problems) out << p.message << "\n";
  return out.str();
}

bool hasProblem(const std::vector<SceneProblem>& problems, Kind kind, Moment moment, const std::string& id) {
  return std::any_of(problems.begin(), problems.end(), [&](const SceneProblem& p) {
    return p.kind == kind && p.moment == moment && !p.ids.empty() && p.ids.front() == id;
  });
}

TEST(CheckSceneGrasp, RearSlotBlockedByTheFrontObjectAtTheGoalPasses) {
  const Scene scene = stockedAtGoal();
  // The premise: with the front cube at its goal, the rear slot cannot be reached; without it, it can.
  ObjectLayout both = ObjectLayout::atGoal(scene);
  EXPECT_FALSE(anyFreeGrasp(scene, 0, *scene.objects[0].X_WO_goal, both));
  ObjectLayout rear_only = both;
  rear_only.remove(1);
  EXPECT_TRUE(anyFreeGrasp(scene, 0, *scene.objects[0].X_WO_goal, rear_only));

  const auto problems = findSceneProblemsDetailed(scene);
  EXPECT_TRUE(problems.empty()) << joined(problems);
  EXPECT_TRUE(findSceneProblems(scene).empty());
}

TEST(CheckSceneGrasp, RearSlotBlockedByTheFrontObjectAtTheStartPasses) {
  // Unstocking: both cubes start in the cubby and go to the table; the front one must leave first.
  Scene scene = cubbyScene();
  addMovable(scene, "rear", kRearSlot, kRearTable);
  addMovable(scene, "front", kFrontSlot, kFrontTable);
  EXPECT_FALSE(anyFreeGrasp(scene, 0, scene.objects[0].X_WO_start, ObjectLayout::atStart(scene)));
  const auto problems = findSceneProblemsDetailed(scene);
  EXPECT_TRUE(problems.empty()) << joined(problems);
}

TEST(CheckSceneGrasp, RearSlotBlockedByAFixedObjectFails) {
  // The front slot holds a fixed cube: nothing can clear the way to the rear slot.
  Scene scene = cubbyScene();
  addMovable(scene, "rear", kRearTable, kRearSlot);
  test::addCube(scene, "stuck", kCube, shelfPose(kFrontSlot));
  scene.objects.back().fixed = true;
  const auto problems = findSceneProblemsDetailed(scene);
  ASSERT_EQ(problems.size(), 1u) << joined(problems);
  EXPECT_TRUE(hasProblem(problems, Kind::kObjectNotGraspable, Moment::kGoal, "rear")) << joined(problems);
  EXPECT_EQ(problems[0].message, "object rear cannot be grasped at its goal by any robot without a collision");
  EXPECT_EQ(problems[0].ids, std::vector<std::string>{"rear"});

  // A fixed cube in front of a rear start: the start fails instead.
  Scene at_start = cubbyScene();
  addMovable(at_start, "rear", kRearSlot, kRearTable);
  test::addCube(at_start, "stuck", kCube, shelfPose(kFrontSlot));
  at_start.objects.back().fixed = true;
  const auto start_problems = findSceneProblemsDetailed(at_start);
  ASSERT_EQ(start_problems.size(), 1u) << joined(start_problems);
  EXPECT_TRUE(hasProblem(start_problems, Kind::kObjectNotGraspable, Moment::kStart, "rear")) << joined(start_problems);
}

TEST(CheckSceneGrasp, RearSlotBlockedByAnObstacleFails) {
  Scene scene = cubbyScene();
  addMovable(scene, "rear", kRearTable, kRearSlot);
  test::addObstacle(scene, "crate", Vec3::Constant(kCube), shelfPose(kFrontSlot));
  const auto problems = findSceneProblemsDetailed(scene);
  ASSERT_EQ(problems.size(), 1u) << joined(problems);
  EXPECT_TRUE(hasProblem(problems, Kind::kObjectNotGraspable, Moment::kGoal, "rear")) << joined(problems);
  EXPECT_EQ(findSceneProblems(scene), std::vector<std::string>{problems[0].message});
}

TEST(CheckSceneGrasp, MovableObjectsStillCountForCollisions) {
  // Both cubes meant for the front slot: the goal collision is reported, naming both, while the grasp
  // rule (which ignores movable objects) has nothing to say.
  Scene scene = cubbyScene();
  addMovable(scene, "a", kRearTable, kFrontSlot);
  addMovable(scene, "b", kFrontTable, kFrontSlot);
  const auto problems = findSceneProblemsDetailed(scene);
  ASSERT_EQ(problems.size(), 1u) << joined(problems);
  EXPECT_EQ(problems[0].kind, Kind::kObjectCollides);
  EXPECT_EQ(problems[0].moment, Moment::kGoal);
  EXPECT_EQ(problems[0].ids, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(problems[0].message, "object a at its goal collides: object a vs object b");
}

TEST(CheckSceneGrasp, StructuredKindsAndIds) {
  // A robot at home inside an obstacle, and a cube floating at its start.
  Scene scene = stockedAtGoal();
  test::addObstacle(scene, "pillar", Vec3(0.1, 0.1, 1.0), makePose(Vec3(0.0, -0.6, 0.5)));
  scene.objects[1].X_WO_start = shelfPose(Vec3(0.57, -0.76, 0.1));
  const auto problems = findSceneProblemsDetailed(scene);
  EXPECT_TRUE(hasProblem(problems, Kind::kRobotAtHomeCollides, Moment::kStart, "ur5e_0")) << joined(problems);
  EXPECT_TRUE(hasProblem(problems, Kind::kRobotAtHomeCollides, Moment::kGoal, "ur5e_0")) << joined(problems);
  EXPECT_TRUE(hasProblem(problems, Kind::kObjectNotResting, Moment::kStart, "front")) << joined(problems);
  for (const SceneProblem& p : problems) {
    if (p.kind != Kind::kRobotAtHomeCollides) continue;
    EXPECT_NE(std::find(p.ids.begin(), p.ids.end(), "pillar"), p.ids.end()) << p.message;
  }
  std::vector<std::string> messages;
  for (const SceneProblem& p : problems) messages.push_back(p.message);
  EXPECT_EQ(findSceneProblems(scene), messages);
}

}  // namespace
}  // namespace dash
