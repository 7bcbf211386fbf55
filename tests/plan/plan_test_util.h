#pragma once
// Shared helpers of the plan tests: the contract's worked example, and small hand-made scenes (two
// arms, a wall, a gantry with a lidded container) with plans built in code.
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "engine/plan/plan.h"
#include "engine/plan/plan_json.h"
#include "engine/robots/kinematics.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_json.h"
#include "tests/common/examples.h"
#include "tests/common/robot_library.h"

namespace dash::test {

inline Scene exampleScene() { return loadScene(exampleScenePath(), library()); }
inline Plan examplePlan() { return loadPlan(examplePlanPath()); }

inline JointVector joints(std::initializer_list<double> values) {
  JointVector q(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double v : values) q[i++] = v;
  return q;
}

inline Pose yaw(const Vec3& p, double angle) { return makePose(p, Quat(Eigen::AngleAxisd(angle, Vec3::UnitZ()))); }

inline TrajectoryPoint point(double t, const JointVector& q) { return TrajectoryPoint{t, q}; }

/// The example scene with a second UR5e 1 m away along -y, its arm (at home) reaching towards the first
/// robot's base; the cube keeps no goal. Panning the first robot by +pi/2 swings its arm into the second.
inline Scene twoArmScene() {
  Scene scene = exampleScene();
  SceneRobot second = scene.robots.front();
  second.id = "ur5e_1";
  second.X_WB = yaw(Vec3(0.0, -1.0, 0.0), -std::numbers::pi / 2.0);
  scene.robots.push_back(second);
  scene.objects.front().X_WO_goal.reset();
  return scene;
}

inline Plan twoArmPlan(const Scene& scene, double pan) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const JointVector home = scene.robots[0].home;
  JointVector turned = home;
  turned[0] += pan;
  const auto& names = scene.robots[0].model->joint_names;
  plan.robots.push_back({"ur5e_0", names, {point(0.0, home), point(1.0, turned), point(2.0, home)}});
  plan.robots.push_back({"ur5e_1", names, {point(0.0, home)}});
  plan.makespan = 2.0;
  return plan;
}

/// A gantry over a deck: a fixed container (10 cm cube) with a 1 cm lid on top, a stand (obstacle
/// plus support surface at z = 0.11) to put the lid on, and a task to inspect the container from 9 cm
/// above its top once the lid is off. The gantry's TCP reaches z in [0.1, 0.4].
inline Scene gantryScene() {
  const std::string text = R"({
    "format": "dashbench.scene/1", "name": "gantry-lid",
    "robots": [{"id": "gantry_0", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp", "inspect"]}],
    "obstacles": [
      {"id": "deck", "shape": {"type": "box", "size": [2.0, 2.0, 0.05]}, "pose": {"p": [0.5, 0.3, -0.025], "q": [0, 0, 0, 1]}},
      {"id": "stand", "shape": {"type": "box", "size": [0.2, 0.2, 0.11]}, "pose": {"p": [0.8, 0.1, 0.055], "q": [0, 0, 0, 1]}}],
    "surfaces": [
      {"id": "deck_top", "z": 0.0, "polygon": [[-0.5, -0.7], [1.5, -0.7], [1.5, 1.3], [-0.5, 1.3]]},
      {"id": "stand_top", "z": 0.11, "polygon": [[0.7, 0.0], [0.9, 0.0], [0.9, 0.2], [0.7, 0.2]]}],
    "objects": [
      {"id": "container_0", "shape": {"type": "box", "size": [0.1, 0.1, 0.1]},
       "start": {"p": [0.5, 0.3, 0.05], "q": [0, 0, 0, 1]}, "fixed": true},
      {"id": "lid_0", "shape": {"type": "box", "size": [0.1, 0.1, 0.01]},
       "start": {"p": [0.5, 0.3, 0.105], "q": [0, 0, 0, 1]}, "fixed": false}],
    "tasks": [{"type": "inspect", "target": "container_0", "pose": {"p": [0.5, 0.3, 0.2], "q": [1, 0, 0, 0]},
               "requires_removed": "lid_0", "capability": "inspect"}]
  })";
  return parseScene(text, library(), "gantry-lid");
}

/// Takes the lid to the stand, inspects, goes home. With remove_lid false it only inspects.
inline Plan gantryPlan(const Scene& scene, bool remove_lid) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const JointVector home = scene.robots[0].home;
  const auto& names = scene.robots[0].model->joint_names;
  RobotTrajectory traj{"gantry_0", names, {point(0.0, home)}};
  double t = 0.0;
  if (remove_lid) {
    // Lid top at z = 0.11 = TCP (q_z = 0.29); on the stand its top is at 0.12 (q_z = 0.28).
    const Pose X_TO = makePose(Vec3(0.0, 0.0, 0.005), Quat(0.0, 1.0, 0.0, 0.0));
    traj.points.push_back(point(t += 1.0, joints({0.5, 0.3, 0.0})));
    traj.points.push_back(point(t += 2.0, joints({0.5, 0.3, 0.29})));
    plan.events.push_back({PlanEvent::Type::kGrasp, t, "gantry_0", "lid_0", X_TO, -1});
    traj.points.push_back(point(t += 2.0, joints({0.5, 0.3, 0.0})));
    traj.points.push_back(point(t += 1.0, joints({0.8, 0.1, 0.0})));
    traj.points.push_back(point(t += 2.0, joints({0.8, 0.1, 0.28})));
    plan.events.push_back({PlanEvent::Type::kRelease, t, "gantry_0", "lid_0", Pose::Identity(), -1});
    traj.points.push_back(point(t += 2.0, joints({0.8, 0.1, 0.0})));
  }
  traj.points.push_back(point(t += 1.5, joints({0.5, 0.3, 0.2})));
  plan.events.push_back({PlanEvent::Type::kInspect, t, "gantry_0", "", Pose::Identity(), 0});
  traj.points.push_back(point(t += 1.5, home));
  plan.robots.push_back(std::move(traj));
  plan.makespan = t;
  return plan;
}

}  // namespace dash::test
