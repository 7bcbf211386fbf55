#include "engine/collision/collision_report.h"

namespace dash {

namespace {

/// "#3": built with append, which g++ 12 does not flag with a false -Wrestrict like "#" + to_string.
std::string numbered(int i) {
  std::string out = "#";
  out.append(std::to_string(i));
  return out;
}

std::string robotId(const Scene& scene, int r) {
  return r >= 0 && r < static_cast<int>(scene.robots.size()) ? scene.robots[static_cast<std::size_t>(r)].id
                                                             : numbered(r);
}

std::string objectId(const Scene& scene, int j) {
  return j >= 0 && j < static_cast<int>(scene.objects.size()) ? scene.objects[static_cast<std::size_t>(j)].id
                                                              : numbered(j);
}

}  // namespace

std::string describe(const CollisionElement& e, const Scene& scene) {
  switch (e.kind) {
    case CollisionElement::Kind::kRobotBody: {
      std::string body = numbered(e.body);
      if (e.robot >= 0 && e.robot < static_cast<int>(scene.robots.size())) {
        const RobotModel* model = scene.robots[static_cast<std::size_t>(e.robot)].model;
        if (model != nullptr && e.body >= 0 && e.body < static_cast<int>(model->bodies.size())) {
          body = model->bodies[static_cast<std::size_t>(e.body)].name;
        }
      }
      return "robot " + robotId(scene, e.robot) + " body " + body;
    }
    case CollisionElement::Kind::kHeldObject:
      return "object " + objectId(scene, e.index) + " (held by " + robotId(scene, e.robot) + ")";
    case CollisionElement::Kind::kObstacle:
      return "obstacle " + (e.index >= 0 && e.index < static_cast<int>(scene.obstacles.size())
                                ? scene.obstacles[static_cast<std::size_t>(e.index)].id
                                : numbered(e.index));
    case CollisionElement::Kind::kObject:
      return "object " + objectId(scene, e.index);
    case CollisionElement::Kind::kNone:
      break;
  }
  return "nothing";
}

std::string describe(const CollisionReport& report, const Scene& scene) {
  return describe(report.a, scene) + " vs " + describe(report.b, scene);
}

}  // namespace dash
