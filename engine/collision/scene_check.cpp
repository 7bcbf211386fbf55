#include "engine/collision/scene_check.h"

#include <array>

#include "engine/collision/collision_queries.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/robots/kinematics.h"
#include "engine/scene/support.h"

namespace dash {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Objects with a goal at the goal, fixed objects at their start, the other movable objects left out.
ObjectLayout goalLayout(const Scene& scene) {
  ObjectLayout layout = ObjectLayout::atGoal(scene);
  for (int j = 0; j < layout.size(); ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (!o.X_WO_goal && !o.fixed) layout.remove(j);
  }
  return layout;
}

void checkRobotsAtHome(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                       const std::string& when, std::vector<std::string>& problems) {
  const Scene& scene = world.scene();
  std::vector<bool> alone_ok(scene.robots.size(), true);
  for (int r = 0; r < world.robotCount(); ++r) {
    CollisionReport report;
    const RobotState state{.robot = r, .q = scene.robots[at(r)].home};
    if (robotInCollision(world, context, state, layout, &report)) {
      alone_ok[at(r)] = false;
      problems.push_back("robot " + scene.robots[at(r)].id + " at home collides (" + when + "): " +
                         describe(report, scene));
    }
  }
  for (int r1 = 0; r1 < world.robotCount(); ++r1) {
    for (int r2 = r1 + 1; r2 < world.robotCount(); ++r2) {
      if (!alone_ok[at(r1)] || !alone_ok[at(r2)]) continue;
      const std::array<RobotState, 2> states{RobotState{.robot = r1, .q = scene.robots[at(r1)].home},
                                             RobotState{.robot = r2, .q = scene.robots[at(r2)].home}};
      CollisionReport report;
      if (robotsInCollision(world, context, states, layout, &report, CheckScope::kStaticOnly)) {
        problems.push_back("robots " + scene.robots[at(r1)].id + " and " + scene.robots[at(r2)].id +
                           " at home collide (" + when + "): " + describe(report, scene));
      }
    }
  }
}

void checkObjects(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                  const std::string& when, std::vector<std::string>& problems) {
  const Scene& scene = world.scene();
  ObjectLayout later = layout;
  for (int j = 0; j < layout.size(); ++j) {
    later.remove(j);
    if (!layout.isPresent(j)) continue;
    const Pose& X_WO = layout.X_WO[at(j)];
    // Each object against obstacles and the objects after it, so each colliding pair is named once;
    // an object that hits an obstacle is still checked against the others.
    ObjectLayout none = ObjectLayout::empty(scene);
    CollisionReport report;
    if (objectInCollision(world, context, j, X_WO, none, &report)) {
      problems.push_back("object " + scene.objects[at(j)].id + " at its " + when + " collides: " + describe(report, scene));
    }
    for (int k = j + 1; k < layout.size(); ++k) {
      if (!layout.isPresent(k)) continue;
      ObjectLayout pair = none;
      pair.place(k, layout.X_WO[at(k)]);
      if (objectInCollision(world, context, j, X_WO, pair, &report)) {
        problems.push_back("object " + scene.objects[at(j)].id + " at its " + when + " collides: " +
                           describe(report, scene));
      }
    }
    const Support support = findSupport(scene, j, X_WO, layout);
    if (!support.found()) {
      problems.push_back("object " + scene.objects[at(j)].id + " does not rest on a surface or another object at its " +
                         when);
    }
  }
}

/// True if some robot with the grasp capability can hold object j at X_WO without a collision.
bool graspable(const CollisionWorld& world, CollisionContext& context, int j, const Pose& X_WO,
               const ObjectLayout& layout) {
  const Scene& scene = world.scene();
  for (int r = 0; r < world.robotCount(); ++r) {
    const SceneRobot& robot = scene.robots[at(r)];
    if (!robot.hasCapability("grasp")) continue;
    for (const GraspCandidate& c : graspCandidates(*robot.model, robot.X_WB, scene.objects[at(j)].shape, X_WO)) {
      for (const JointVector& q : inverseKinematics(*robot.model, robot.X_WB, c.X_WT)) {
        const RobotState state{.robot = r, .q = q, .held = {.object = j, .X_TO = c.X_TO}};
        if (!robotInCollision(world, context, state, layout)) return true;
      }
    }
  }
  return false;
}

}  // namespace

std::vector<std::string> findSceneProblems(const Scene& scene) {
  std::vector<std::string> problems;
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout start = ObjectLayout::atStart(scene);
  const ObjectLayout goal = goalLayout(scene);

  checkRobotsAtHome(world, context, start, "objects at start", problems);
  if (scene.end_at_home) checkRobotsAtHome(world, context, goal, "objects at goal", problems);
  checkObjects(world, context, start, "start", problems);
  ObjectLayout goals_only = goal;
  for (int j = 0; j < goal.size(); ++j) {
    if (!scene.objects[at(j)].X_WO_goal) goals_only.remove(j);
  }
  // Fixed objects were checked at the start; at the goal, check the objects that move there (their
  // supports and neighbours come from the whole goal layout).
  for (int j = 0; j < goal.size(); ++j) {
    if (!goals_only.isPresent(j)) continue;
    ObjectLayout others = goal;
    others.remove(j);
    CollisionReport report;
    // Against obstacles and fixed objects or goals with a lower index already checked: name pairs once.
    for (int k = 0; k < goal.size(); ++k) {
      if (k < j && goals_only.isPresent(k)) others.remove(k);
    }
    if (objectInCollision(world, context, j, goal.X_WO[at(j)], others, &report)) {
      problems.push_back("object " + scene.objects[at(j)].id + " at its goal collides: " + describe(report, scene));
    }
    if (!findSupport(scene, j, goal.X_WO[at(j)], goal).found()) {
      problems.push_back("object " + scene.objects[at(j)].id + " does not rest on a surface or another object at its goal");
    }
  }

  for (int j = 0; j < static_cast<int>(scene.objects.size()); ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (o.fixed) continue;
    if (!graspable(world, context, j, o.X_WO_start, start)) {
      problems.push_back("object " + o.id + " cannot be grasped at its start by any robot without a collision");
    }
    if (o.X_WO_goal && !graspable(world, context, j, *o.X_WO_goal, goal)) {
      problems.push_back("object " + o.id + " cannot be grasped at its goal by any robot without a collision");
    }
  }
  return problems;
}

}  // namespace dash
