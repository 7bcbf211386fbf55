#include "engine/scenarios/scenario_validation.h"

#include <algorithm>

#include "engine/collision/collision_queries.h"
#include "engine/collision/scene_check.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

std::string robotList(const Scene& scene, const std::vector<int>& robots) {
  if (robots.empty()) return "none";
  std::string s;
  for (const int r : robots) s += (s.empty() ? "" : ", ") + scene.robots[at(r)].id;
  return s;
}

const BlockedGrasp* findBlocked(const ValidationSpec& spec, int object, bool at_goal) {
  for (const BlockedGrasp& b : spec.blocked) {
    if (b.object == object && b.at_goal == at_goal) return &b;
  }
  return nullptr;
}

/// The check-scene line for an object that cannot be grasped at one end (scene_check.cpp's wording).
std::string graspProblemLine(const Scene& scene, int object, bool at_goal) {
  return "object " + scene.objects[at(object)].id + " cannot be grasped at its " + (at_goal ? "goal" : "start") +
         " by any robot without a collision";
}

/// Layout for grasping `object` at one end: the check-scene layout, less the design blockers.
ObjectLayout graspLayout(const Scene& scene, const ValidationSpec& spec, int object, bool at_goal) {
  ObjectLayout layout = at_goal ? goalCheckLayout(scene) : ObjectLayout::atStart(scene);
  if (const BlockedGrasp* b = findBlocked(spec, object, at_goal)) {
    for (const int k : b->blockers) layout.remove(k);
  }
  return layout;
}

void checkTasks(const CollisionWorld& world, CollisionContext& context, std::vector<std::string>& problems) {
  const Scene& scene = world.scene();
  for (std::size_t t = 0; t < scene.tasks.size(); ++t) {
    const SceneTask& task = scene.tasks[t];
    ObjectLayout layout = ObjectLayout::atStart(scene);
    if (task.requires_removed_object >= 0) layout.remove(task.requires_removed_object);
    bool reached = false;
    for (int r = 0; r < world.robotCount() && !reached; ++r) {
      const SceneRobot& robot = scene.robots[at(r)];
      if (!robot.hasCapability(task.capability)) continue;
      for (const JointVector& q : inverseKinematics(*robot.model, robot.X_WB, task.X_WT)) {
        if (!robotInCollision(world, context, RobotState{.robot = r, .q = q}, layout)) {
          reached = true;
          break;
        }
      }
    }
    if (!reached) {
      problems.push_back("task " + std::to_string(t) + " (inspect " + task.target + "): no robot with capability \"" +
                         task.capability + "\" reaches its pose without a collision");
    }
  }
}

}  // namespace

ObjectLayout goalCheckLayout(const Scene& scene) {
  ObjectLayout layout = ObjectLayout::atGoal(scene);
  for (int j = 0; j < layout.size(); ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (!o.X_WO_goal && !o.fixed) layout.remove(j);
  }
  return layout;
}

ScenarioReport validateScenario(const Scene& scene, const ValidationSpec& spec) {
  ScenarioReport report;
  const CollisionWorld world(scene);
  CollisionContext context(world);

  // check-scene, with the grasp lines of design-blocked grasps replaced by the check without blockers.
  for (std::string& line : findSceneProblems(scene)) {
    bool replaced = false;
    for (const BlockedGrasp& b : spec.blocked) {
      if (line != graspProblemLine(scene, b.object, b.at_goal)) continue;
      replaced = true;
      const SceneObject& o = scene.objects[at(b.object)];
      const Pose& X_WO = b.at_goal ? *o.X_WO_goal : o.X_WO_start;
      if (robotsAbleToGrasp(world, context, b.object, X_WO, graspLayout(scene, spec, b.object, b.at_goal)).empty()) {
        report.problems.push_back(line + " (even with its blockers away)");
      }
    }
    if (!replaced) report.problems.push_back(std::move(line));
  }
  checkTasks(world, context, report.problems);
  if (!spec.handover_chains || !report.problems.empty()) return report;

  // Handover chains. All objects of a chain family share one shape; the graph is built for the first
  // movable object and reused for the others of the same size.
  int representative = -1;
  for (int j = 0; j < world.objectCount(); ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (o.fixed || !o.X_WO_goal) continue;
    if (representative < 0) {
      representative = j;
      report.graph = buildHandoverGraph(world, context, j, spec.handover_search);
    } else if (!o.shape.size.isApprox(scene.objects[at(representative)].shape.size)) {
      report.problems.push_back("object " + o.id + ": handover chains are checked for one object size only");
      continue;
    }
    ObjectTransfer transfer;
    transfer.object = j;
    transfer.start_robots = robotsAbleToGrasp(world, context, j, o.X_WO_start, graspLayout(scene, spec, j, false));
    transfer.goal_robots = robotsAbleToGrasp(world, context, j, *o.X_WO_goal, graspLayout(scene, spec, j, true));
    transfer.min_handovers = minHandovers(report.graph, transfer.start_robots, transfer.goal_robots);
    if (transfer.min_handovers < 0) {
      report.problems.push_back("object " + o.id + ": no chain of handovers links the robots that can grasp its start (" +
                                robotList(scene, transfer.start_robots) + ") to those that can grasp its goal (" +
                                robotList(scene, transfer.goal_robots) + ")");
    }
    report.transfers.push_back(std::move(transfer));
  }
  return report;
}

}  // namespace dash
