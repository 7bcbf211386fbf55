#include "engine/collision/scene_check.h"

#include <algorithm>
#include <array>

#include "engine/collision/collision_queries.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/robots/kinematics.h"
#include "engine/scene/support.h"

namespace dash {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

using Kind = SceneProblem::Kind;
using Moment = SceneProblem::Moment;

const char* momentName(Moment moment) { return moment == Moment::kGoal ? "goal" : "start"; }

/// The scene id behind one side of a colliding pair (a robot body stands for its robot).
std::string elementId(const CollisionElement& e, const Scene& scene) {
  switch (e.kind) {
    case CollisionElement::Kind::kRobotBody:
      return scene.robots[at(e.robot)].id;
    case CollisionElement::Kind::kHeldObject:
    case CollisionElement::Kind::kObject:
      return scene.objects[at(e.index)].id;
    case CollisionElement::Kind::kObstacle:
      return scene.obstacles[at(e.index)].id;
    case CollisionElement::Kind::kNone:
      break;
  }
  return {};
}

/// Collects the problems; ids are the subject followed by whatever else the report names, once each.
class Problems {
 public:
  explicit Problems(const Scene& scene) : scene_(scene) {}

  void add(Kind kind, Moment moment, std::string message, std::vector<std::string> ids,
           const CollisionReport* report = nullptr) {
    if (report != nullptr) {
      for (const CollisionElement* e : {&report->a, &report->b}) {
        std::string id = elementId(*e, scene_);
        if (!id.empty() && std::find(ids.begin(), ids.end(), id) == ids.end()) ids.push_back(std::move(id));
      }
    }
    list_.push_back({.kind = kind, .moment = moment, .message = std::move(message), .ids = std::move(ids)});
  }

  std::vector<SceneProblem> take() { return std::move(list_); }

 private:
  const Scene& scene_;
  std::vector<SceneProblem> list_;
};

/// Objects with a goal at the goal, fixed objects at their start, the other movable objects left out.
ObjectLayout goalLayout(const Scene& scene) {
  ObjectLayout layout = ObjectLayout::atGoal(scene);
  for (int j = 0; j < layout.size(); ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (!o.X_WO_goal && !o.fixed) layout.remove(j);
  }
  return layout;
}

/// The fixed objects of `layout` only: what the grasp check treats as in the way besides obstacles.
ObjectLayout fixedOnly(const Scene& scene, ObjectLayout layout) {
  for (int j = 0; j < layout.size(); ++j) {
    if (!scene.objects[at(j)].fixed) layout.remove(j);
  }
  return layout;
}

void checkRobotsAtHome(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                       Moment moment, Problems& problems) {
  const Scene& scene = world.scene();
  const std::string when = std::string("objects at ") + momentName(moment);
  std::vector<bool> alone_ok(scene.robots.size(), true);
  for (int r = 0; r < world.robotCount(); ++r) {
    CollisionReport report;
    const RobotState state{.robot = r, .q = scene.robots[at(r)].home};
    if (robotInCollision(world, context, state, layout, &report)) {
      alone_ok[at(r)] = false;
      const std::string& id = scene.robots[at(r)].id;
      problems.add(Kind::kRobotAtHomeCollides, moment,
                   "robot " + id + " at home collides (" + when + "): " + describe(report, scene), {id}, &report);
    }
  }
  for (int r1 = 0; r1 < world.robotCount(); ++r1) {
    for (int r2 = r1 + 1; r2 < world.robotCount(); ++r2) {
      if (!alone_ok[at(r1)] || !alone_ok[at(r2)]) continue;
      const std::array<RobotState, 2> states{RobotState{.robot = r1, .q = scene.robots[at(r1)].home},
                                             RobotState{.robot = r2, .q = scene.robots[at(r2)].home}};
      CollisionReport report;
      if (robotsInCollision(world, context, states, layout, &report, CheckScope::kStaticOnly)) {
        const std::string& id1 = scene.robots[at(r1)].id;
        const std::string& id2 = scene.robots[at(r2)].id;
        problems.add(Kind::kRobotsAtHomeCollide, moment,
                     "robots " + id1 + " and " + id2 + " at home collide (" + when + "): " + describe(report, scene),
                     {id1, id2}, &report);
      }
    }
  }
}

void addObjectCollision(const Scene& scene, int j, Moment moment, const CollisionReport& report,
                        Problems& problems) {
  const std::string& id = scene.objects[at(j)].id;
  problems.add(Kind::kObjectCollides, moment,
               "object " + id + " at its " + momentName(moment) + " collides: " + describe(report, scene), {id},
               &report);
}

void addNotResting(const Scene& scene, int j, Moment moment, Problems& problems) {
  const std::string& id = scene.objects[at(j)].id;
  problems.add(Kind::kObjectNotResting, moment,
               "object " + id + " does not rest on a surface or another object at its " + momentName(moment), {id});
}

void checkObjectsAtStart(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& layout,
                         Problems& problems) {
  const Scene& scene = world.scene();
  for (int j = 0; j < layout.size(); ++j) {
    if (!layout.isPresent(j)) continue;
    const Pose& X_WO = layout.X_WO[at(j)];
    // Each object against obstacles and the objects after it, so each colliding pair is named once;
    // an object that hits an obstacle is still checked against the others.
    const ObjectLayout none = ObjectLayout::empty(scene);
    CollisionReport report;
    if (objectInCollision(world, context, j, X_WO, none, &report)) {
      addObjectCollision(scene, j, Moment::kStart, report, problems);
    }
    for (int k = j + 1; k < layout.size(); ++k) {
      if (!layout.isPresent(k)) continue;
      ObjectLayout pair = none;
      pair.place(k, layout.X_WO[at(k)]);
      if (objectInCollision(world, context, j, X_WO, pair, &report)) {
        addObjectCollision(scene, j, Moment::kStart, report, problems);
      }
    }
    if (!findSupport(scene, j, X_WO, layout).found()) addNotResting(scene, j, Moment::kStart, problems);
  }
}

/// Fixed objects were checked at the start; at the goal, the objects that move there (their supports
/// and neighbours come from the whole goal layout).
void checkObjectsAtGoal(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& goal,
                        Problems& problems) {
  const Scene& scene = world.scene();
  for (int j = 0; j < goal.size(); ++j) {
    if (!scene.objects[at(j)].X_WO_goal) continue;
    ObjectLayout others = goal;
    others.remove(j);
    // Against obstacles and fixed objects or goals with a lower index already checked: name pairs once.
    for (int k = 0; k < j; ++k) {
      if (scene.objects[at(k)].X_WO_goal) others.remove(k);
    }
    CollisionReport report;
    if (objectInCollision(world, context, j, goal.X_WO[at(j)], others, &report)) {
      addObjectCollision(scene, j, Moment::kGoal, report, problems);
    }
    if (!findSupport(scene, j, goal.X_WO[at(j)], goal).found()) addNotResting(scene, j, Moment::kGoal, problems);
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

void checkGrasps(const CollisionWorld& world, CollisionContext& context, const ObjectLayout& start,
                 const ObjectLayout& goal, Problems& problems) {
  const Scene& scene = world.scene();
  // Only obstacles and fixed objects stand in the way (see the header): movable ones can be moved first
  // or placed later, so their blocking is a matter of ordering, which the planners decide.
  const ObjectLayout fixed_at_start = fixedOnly(scene, start);
  const ObjectLayout fixed_at_goal = fixedOnly(scene, goal);
  for (int j = 0; j < static_cast<int>(scene.objects.size()); ++j) {
    const SceneObject& o = scene.objects[at(j)];
    if (o.fixed) continue;
    if (!graspable(world, context, j, o.X_WO_start, fixed_at_start)) {
      problems.add(Kind::kObjectNotGraspable, Moment::kStart,
                   "object " + o.id + " cannot be grasped at its start by any robot without a collision", {o.id});
    }
    if (o.X_WO_goal && !graspable(world, context, j, *o.X_WO_goal, fixed_at_goal)) {
      problems.add(Kind::kObjectNotGraspable, Moment::kGoal,
                   "object " + o.id + " cannot be grasped at its goal by any robot without a collision", {o.id});
    }
  }
}

}  // namespace

std::vector<SceneProblem> findSceneProblemsDetailed(const Scene& scene) {
  Problems problems(scene);
  const CollisionWorld world(scene);
  CollisionContext context(world);
  const ObjectLayout start = ObjectLayout::atStart(scene);
  const ObjectLayout goal = goalLayout(scene);

  checkRobotsAtHome(world, context, start, Moment::kStart, problems);
  if (scene.end_at_home) checkRobotsAtHome(world, context, goal, Moment::kGoal, problems);
  checkObjectsAtStart(world, context, start, problems);
  checkObjectsAtGoal(world, context, goal, problems);
  checkGrasps(world, context, start, goal, problems);
  return problems.take();
}

std::vector<std::string> findSceneProblems(const Scene& scene) {
  std::vector<std::string> lines;
  for (SceneProblem& p : findSceneProblemsDetailed(scene)) lines.push_back(std::move(p.message));
  return lines;
}

}  // namespace dash
