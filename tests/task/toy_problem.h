#pragma once
// Hand-built task problems on a line of robots: no geometry, reachability given by rules.
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "engine/scene/scene.h"
#include "engine/task/reachability.h"

namespace dash::test {

/// Robots at x = 0, 1, 2, ...; objects at y = 0.5 with the given start and goal x.
inline Scene lineScene(int robots, const std::vector<std::pair<double, double>>& object_start_goal_x) {
  Scene scene;
  scene.name = "toy";
  for (int r = 0; r < robots; ++r) {
    SceneRobot robot;
    robot.id = "r" + std::to_string(r);
    robot.model_name = "toy";
    robot.X_WB = makePose(Vec3(r, 0, 0));
    robot.capabilities = {"grasp"};
    scene.robots.push_back(robot);
  }
  for (std::size_t j = 0; j < object_start_goal_x.size(); ++j) {
    SceneObject o;
    o.id = "o" + std::to_string(j);
    o.shape.size = Vec3(0.04, 0.04, 0.04);
    o.X_WO_start = makePose(Vec3(object_start_goal_x[j].first, 0.5, 0.02));
    o.X_WO_goal = makePose(Vec3(object_start_goal_x[j].second, 0.5, 0.02));
    scene.objects.push_back(o);
  }
  return scene;
}

/// Robot r reaches objects within 0.6 in x with top and side grasps; neighbours hand over.
inline TaskReachability lineReachability(const Scene& scene) {
  TaskReachability reach;
  reach.canGrasp = [&scene](int r, int, const Pose& X, GraspClass g) {
    return g != GraspClass::kBottom && std::abs(X.translation().x() - scene.robots[r].X_WB.translation().x()) < 0.6;
  };
  reach.canHandover = [](int a, int b, int, GraspClass g1, GraspClass g2) {
    return std::abs(a - b) == 1 && g1 != GraspClass::kBottom && g2 != GraspClass::kBottom;
  };
  reach.canInspect = [](int, int) { return true; };
  reach.graspCost = [&scene](int r, const Pose& X) {
    return (X.translation() - scene.robots[r].X_WB.translation()).norm();
  };
  reach.handoverCost = [](int a, int b) { return std::abs(a - b) * 1.0; };
  return reach;
}

}  // namespace dash::test
