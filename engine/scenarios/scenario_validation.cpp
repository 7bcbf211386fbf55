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

/// Layout for the generator's grasp check of `object` at one end: every other object at that end (at
/// the goal: goalCheckLayout), less the design blockers.
ObjectLayout graspLayout(const Scene& scene, const ValidationSpec& spec, int object, bool at_goal) {
  ObjectLayout layout = at_goal ? goalCheckLayout(scene) : ObjectLayout::atStart(scene);
  if (const BlockedGrasp* b = findBlocked(spec, object, at_goal)) {
    for (const int k : b->blockers) layout.remove(k);
  }
  return layout;
}

/// True if check-scene already says that no robot can grasp object `id` at that end.
bool reportedUngraspable(const std::vector<SceneProblem>& problems, const std::string& id,
                         SceneProblem::Moment moment) {
  return std::any_of(problems.begin(), problems.end(), [&](const SceneProblem& p) {
    return p.kind == SceneProblem::Kind::kObjectNotGraspable && p.moment == moment && !p.ids.empty() &&
           p.ids.front() == id;
  });
}

std::string amongObjectsProblem(const ValidationSpec& spec, const SceneObject& o, int object, bool at_goal) {
  const std::string end = at_goal ? "goal" : "start";
  return "object " + o.id + " cannot be grasped at its " + end + " with the other objects at their " + end +
         (findBlocked(spec, object, at_goal) != nullptr ? " (even with its blockers away)" : "");
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

  // check-scene, as the command runs it.
  const std::vector<SceneProblem> scene_problems = findSceneProblemsDetailed(scene);
  for (const SceneProblem& p : scene_problems) report.problems.push_back(p.message);
  checkTasks(world, context, report.problems);

  // The generator's own, stricter grasp check. check-scene ignores the other movable objects; a
  // generated scene also promises that each grasp works with them in place (at the start, or at their
  // goals), except for the blockers it declares. The robots found feed the handover chains below.
  const int objects = world.objectCount();
  std::vector<std::vector<int>> start_robots(at(objects)), goal_robots(at(objects));
  for (int j = 0; j < objects; ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (o.fixed) continue;
    start_robots[at(j)] = robotsAbleToGrasp(world, context, j, o.X_WO_start, graspLayout(scene, spec, j, false));
    if (start_robots[at(j)].empty() && !reportedUngraspable(scene_problems, o.id, SceneProblem::Moment::kStart)) {
      report.problems.push_back(amongObjectsProblem(spec, o, j, false));
    }
    if (!o.X_WO_goal) continue;
    goal_robots[at(j)] = robotsAbleToGrasp(world, context, j, *o.X_WO_goal, graspLayout(scene, spec, j, true));
    if (goal_robots[at(j)].empty() && !reportedUngraspable(scene_problems, o.id, SceneProblem::Moment::kGoal)) {
      report.problems.push_back(amongObjectsProblem(spec, o, j, true));
    }
  }
  if (!spec.handover_chains || !report.problems.empty()) return report;

  // Handover chains. All objects of a chain family share one shape; the graph is built for the first
  // movable object and reused for the others of the same size.
  int representative = -1;
  for (int j = 0; j < objects; ++j) {
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
    transfer.start_robots = start_robots[at(j)];
    transfer.goal_robots = goal_robots[at(j)];
    transfer.min_handovers = minHandovers(report.graph, transfer.start_robots, transfer.goal_robots);
    if (transfer.min_handovers < 0) {
      report.problems.push_back("object " + o.id +
                                ": no chain of handovers links the robots that can grasp its start (" +
                                robotList(scene, transfer.start_robots) + ") to those that can grasp its goal (" +
                                robotList(scene, transfer.goal_robots) + ")");
    }
    report.transfers.push_back(std::move(transfer));
  }
  return report;
}

}  // namespace dash
