#pragma once
// Hand-made scenes and plans for the certified validator's tests: each dips a part a set depth into
// something between two plan points (or keeps it a set distance away), so the test knows the answer.
#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/collision/distance_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/plan/plan.h"
#include "engine/robots/kinematics.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_json.h"
#include "plan_test_util.h"

namespace dash::test {

/// A gantry, a deck and a 4 cm cube at (0.3, 0.2). The gantry carries the cube at TCP height 0.2 on
/// the diagonal from (0.3, 0.2) to (0.6, 0.5); a "shelf" box below z = 0.29 stands so that the cube's
/// (+x, -y) corner passes its vertical edge `overlap` deep (negative: that far outside in x and in y),
/// 2.5 mm of the corner's travel past the 1 cm sampler's nearest samples.
inline Scene shelfEdgeScene(double overlap) {
  // The corner travels (0.32 + s, 0.18 + s); it is inside the shelf for s in [s* - p, s* + p].
  constexpr double kCentre = 0.1525;
  const double x_edge = 0.32 + kCentre - overlap;
  const double y_edge = 0.18 + kCentre + overlap;
  const std::string shelf = "[" + std::to_string(x_edge + 0.1) + ", " + std::to_string(y_edge - 0.1) + ", 0.195]";
  const std::string text = R"({
    "format": "dashbench.scene/1", "name": "shelf-edge", "end_at_home": false,
    "robots": [{"id": "gantry_0", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]}],
    "obstacles": [
      {"id": "deck", "shape": {"type": "box", "size": [2.0, 2.0, 0.05]}, "pose": {"p": [0.5, 0.3, 0.075], "q": [0, 0, 0, 1]}},
      {"id": "shelf", "shape": {"type": "box", "size": [0.2, 0.2, 0.19]}, "pose": {"p": )" + shelf + R"(, "q": [0, 0, 0, 1]}}],
    "surfaces": [{"id": "deck_top", "z": 0.1, "polygon": [[-0.5, -0.7], [1.5, -0.7], [1.5, 1.3], [-0.5, 1.3]]}],
    "objects": [{"id": "cube_0", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]},
                 "start": {"p": [0.3, 0.2, 0.12], "q": [0, 0, 0, 1]}, "fixed": false}],
    "tasks": []
  })";
  return parseScene(text, library(), "shelf-edge");
}

/// Picks the cube up, carries it past the shelf's edge, puts it down at (0.6, 0.5).
inline Plan shelfEdgePlan(const Scene& scene) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const Pose X_TO = makePose(Vec3(0.0, 0.0, 0.02), Quat(0.0, 1.0, 0.0, 0.0));  // cube top at the TCP
  RobotTrajectory traj{"gantry_0", scene.robots[0].model->joint_names, {point(0.0, scene.robots[0].home)}};
  traj.points.push_back(point(1.0, joints({0.3, 0.2, 0.0})));
  traj.points.push_back(point(4.0, joints({0.3, 0.2, 0.26})));
  plan.events.push_back({PlanEvent::Type::kGrasp, 4.0, "gantry_0", "cube_0", X_TO, -1});
  traj.points.push_back(point(6.0, joints({0.3, 0.2, 0.1})));
  traj.points.push_back(point(7.0, joints({0.6, 0.5, 0.1})));
  traj.points.push_back(point(9.0, joints({0.6, 0.5, 0.26})));
  plan.events.push_back({PlanEvent::Type::kRelease, 9.0, "gantry_0", "cube_0", Pose::Identity(), -1});
  traj.points.push_back(point(12.0, joints({0.6, 0.5, 0.0})));
  plan.robots.push_back(std::move(traj));
  plan.makespan = 12.0;
  return plan;
}

/// A gantry, a deck, the cube it picks up at (0.3, 0.2) and a second cube at (0.5, 0.2) that it only
/// passes over (neighbourCubePlan).
inline Scene neighbourCubeScene() {
  const std::string text = R"({
    "format": "dashbench.scene/1", "name": "neighbour-cube", "end_at_home": false,
    "robots": [{"id": "gantry_0", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]}],
    "obstacles": [
      {"id": "deck", "shape": {"type": "box", "size": [2.0, 2.0, 0.05]}, "pose": {"p": [0.5, 0.3, 0.075], "q": [0, 0, 0, 1]}}],
    "surfaces": [{"id": "deck_top", "z": 0.1, "polygon": [[-0.5, -0.7], [1.5, -0.7], [1.5, 1.3], [-0.5, 1.3]]}],
    "objects": [{"id": "cube_0", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]},
                 "start": {"p": [0.3, 0.2, 0.12], "q": [0, 0, 0, 1]}, "fixed": false},
                {"id": "cube_1", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]},
                 "start": {"p": [0.5, 0.2, 0.12], "q": [0, 0, 0, 1]}, "fixed": false}],
    "tasks": []
  })";
  return parseScene(text, library(), "neighbour-cube");
}

/// The tool comes down onto cube_1's top face `dip` deep (negative: stops that far above) and goes back
/// up, then grasps cube_0 (the tool touches its top face), lifts it and puts it back.
inline Plan neighbourCubePlan(const Scene& scene, double dip) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const Pose X_TO = makePose(Vec3(0.0, 0.0, 0.02), Quat(0.0, 1.0, 0.0, 0.0));  // cube top at the TCP
  RobotTrajectory traj{"gantry_0", scene.robots[0].model->joint_names, {point(0.0, scene.robots[0].home)}};
  traj.points.push_back(point(1.0, joints({0.5, 0.2, 0.0})));
  traj.points.push_back(point(4.0, joints({0.5, 0.2, 0.26 + dip})));  // TCP z = 0.4 - q_z; top at 0.14
  traj.points.push_back(point(7.0, joints({0.5, 0.2, 0.0})));
  traj.points.push_back(point(8.0, joints({0.3, 0.2, 0.0})));
  traj.points.push_back(point(11.0, joints({0.3, 0.2, 0.26})));
  plan.events.push_back({PlanEvent::Type::kGrasp, 11.0, "gantry_0", "cube_0", X_TO, -1});
  traj.points.push_back(point(13.0, joints({0.3, 0.2, 0.1})));
  traj.points.push_back(point(15.0, joints({0.3, 0.2, 0.26})));
  plan.events.push_back({PlanEvent::Type::kRelease, 15.0, "gantry_0", "cube_0", Pose::Identity(), -1});
  traj.points.push_back(point(18.0, joints({0.3, 0.2, 0.0})));
  plan.robots.push_back(std::move(traj));
  plan.makespan = 18.0;
  return plan;
}

/// Two gantries 0.6 m apart, each over its own cube (cube_0 at x 0.3, cube_1 at x 0.9).
inline Scene twoGantriesScene() {
  const std::string text = R"({
    "format": "dashbench.scene/1", "name": "two-gantries", "end_at_home": false,
    "robots": [{"id": "gantry_0", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]},
               {"id": "gantry_1", "model": "gantry3", "base": {"p": [0.6, 0, 0], "q": [0, 0, 0, 1]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]}],
    "obstacles": [
      {"id": "deck", "shape": {"type": "box", "size": [2.0, 2.0, 0.05]}, "pose": {"p": [0.5, 0.3, 0.075], "q": [0, 0, 0, 1]}}],
    "surfaces": [{"id": "deck_top", "z": 0.1, "polygon": [[-0.5, -0.7], [1.5, -0.7], [1.5, 1.3], [-0.5, 1.3]]}],
    "objects": [{"id": "cube_0", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]},
                 "start": {"p": [0.3, 0.2, 0.12], "q": [0, 0, 0, 1]}, "fixed": false},
                {"id": "cube_1", "shape": {"type": "box", "size": [0.04, 0.04, 0.04]},
                 "start": {"p": [0.9, 0.2, 0.12], "q": [0, 0, 0, 1]}, "fixed": false}],
    "tasks": []
  })";
  return parseScene(text, library(), "two-gantries");
}

/// A gantry's grasp of a cube's top: the cube's top face at the TCP.
inline Pose cubeTopGrasp() { return makePose(Vec3(0.0, 0.0, 0.02), Quat(0.0, 1.0, 0.0, 0.0)); }

/// twoGantriesScene's gantry_0 from home over cube_0, grasping it at t=4, lifting it and putting it back
/// (release at t=6): its trajectory so far, the two events added to `plan`.
inline RobotTrajectory liftAndPutBackCube0(const Scene& scene, Plan& plan) {
  RobotTrajectory a{"gantry_0", scene.robots[0].model->joint_names, {point(0.0, scene.robots[0].home)}};
  a.points.push_back(point(1.0, joints({0.3, 0.2, 0.0})));
  a.points.push_back(point(4.0, joints({0.3, 0.2, 0.26})));  // TCP z = 0.4 - q_z: cube_0's top
  plan.events.push_back({PlanEvent::Type::kGrasp, 4.0, "gantry_0", "cube_0", cubeTopGrasp(), -1});
  a.points.push_back(point(5.0, joints({0.3, 0.2, 0.2})));
  a.points.push_back(point(6.0, joints({0.3, 0.2, 0.26})));
  plan.events.push_back({PlanEvent::Type::kRelease, 6.0, "gantry_0", "cube_0", Pose::Identity(), -1});
  return a;
}

/// gantry_0 lifts cube_0 and puts it back (release at t=6), then presses its tool `press` deep into the
/// cube's top from t=7 to t=10 before it rises; meanwhile gantry_1 grasps cube_1 at t=7.5 and releases it
/// at t=8.5, so gantry_0's press spans epochs that neither follow nor precede its own release directly.
inline Plan pressAfterReleasePlan(const Scene& scene, double press) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const Pose X_TO = cubeTopGrasp();
  const auto& names = scene.robots[0].model->joint_names;
  RobotTrajectory a = liftAndPutBackCube0(scene, plan);
  a.points.push_back(point(7.0, joints({0.3, 0.2, 0.26 + press})));
  a.points.push_back(point(10.0, joints({0.3, 0.2, 0.26 + press})));
  a.points.push_back(point(13.0, joints({0.3, 0.2, 0.0})));
  RobotTrajectory b{"gantry_1", names, {point(0.0, scene.robots[1].home)}};
  b.points.push_back(point(1.0, joints({0.3, 0.2, 0.0})));
  b.points.push_back(point(7.5, joints({0.3, 0.2, 0.26})));
  plan.events.push_back({PlanEvent::Type::kGrasp, 7.5, "gantry_1", "cube_1", X_TO, -1});
  b.points.push_back(point(8.0, joints({0.3, 0.2, 0.2})));
  b.points.push_back(point(8.5, joints({0.3, 0.2, 0.26})));
  plan.events.push_back({PlanEvent::Type::kRelease, 8.5, "gantry_1", "cube_1", Pose::Identity(), -1});
  b.points.push_back(point(13.0, joints({0.3, 0.2, 0.0})));
  plan.robots.push_back(std::move(a));
  plan.robots.push_back(std::move(b));
  plan.makespan = 13.0;
  return plan;
}

/// Two gantries hand a 12 x 4 x 2 cm bar over on a stand: gantry_0 grasps its top left of centre,
/// gantry_1 (mounted 15 cm higher, turned by pi) comes down right of centre and takes it over. Their
/// 6 cm tools end `overlap` deep into each other along x (negative: that far apart).
inline Scene handoverScene() {
  const std::string text = R"({
    "format": "dashbench.scene/1", "name": "handover", "end_at_home": false,
    "robots": [{"id": "gantry_0", "model": "gantry3", "base": {"p": [0, 0, 0], "q": [0, 0, 0, 1]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]},
               {"id": "gantry_1", "model": "gantry3", "base": {"p": [1.0, 0.6, 0.15], "q": [0, 0, 1, 0]},
                "home": [0.1, 0.1, 0.0], "capabilities": ["grasp"]}],
    "obstacles": [
      {"id": "deck", "shape": {"type": "box", "size": [2.0, 2.0, 0.05]}, "pose": {"p": [0.5, 0.3, -0.025], "q": [0, 0, 0, 1]}},
      {"id": "stand", "shape": {"type": "box", "size": [0.2, 0.1, 0.28]}, "pose": {"p": [0.5, 0.3, 0.14], "q": [0, 0, 0, 1]}}],
    "surfaces": [{"id": "stand_top", "z": 0.28, "polygon": [[0.4, 0.25], [0.6, 0.25], [0.6, 0.35], [0.4, 0.35]]}],
    "objects": [{"id": "bar_0", "shape": {"type": "box", "size": [0.12, 0.04, 0.02]},
                 "start": {"p": [0.5, 0.3, 0.29], "q": [0, 0, 0, 1]}, "fixed": false}],
    "tasks": []
  })";
  return parseScene(text, library(), "handover");
}

inline Plan handoverPlan(const Scene& scene, double overlap) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const auto& names = scene.robots[0].model->joint_names;
  const Pose X_WO = scene.objects[0].X_WO_start;
  const double x0 = 0.5 - 0.03;                   // gantry_0's TCP, world x
  const double x1 = 0.5 + 0.03 - overlap;         // gantry_1's TCP, world x
  const JointVector q0 = joints({x0, 0.3, 0.1});  // TCP at z = 0.3, the bar's top
  const JointVector q1 = joints({1.0 - x1, 0.3, 0.25});
  auto attach = [&](int r, const JointVector& q) {
    const SceneRobot& robot = scene.robots[static_cast<std::size_t>(r)];
    return Pose(forwardKinematics(*robot.model, robot.X_WB, q).X_WT.inverse() * X_WO);
  };
  JointVector above0 = q0;
  above0[2] = 0.0;
  JointVector above1 = q1;
  above1[2] = 0.0;
  plan.robots.push_back({"gantry_0", names, {point(0.0, scene.robots[0].home), point(1.0, above0), point(2.0, q0),
                                            point(5.0, q0), point(6.0, above0)}});
  plan.robots.push_back({"gantry_1", names, {point(0.0, scene.robots[1].home), point(2.0, above1), point(4.0, q1),
                                            point(5.0, q1), point(7.0, above1)}});
  plan.events.push_back({PlanEvent::Type::kGrasp, 2.0, "gantry_0", "bar_0", attach(0, q0), -1});
  plan.events.push_back({PlanEvent::Type::kGrasp, 4.0, "gantry_1", "bar_0", attach(1, q1), -1});
  plan.events.push_back({PlanEvent::Type::kRelease, 4.0, "gantry_0", "bar_0", Pose::Identity(), -1});
  plan.events.push_back({PlanEvent::Type::kRelease, 5.0, "gantry_1", "bar_0", Pose::Identity(), -1});
  plan.makespan = 7.0;
  return plan;
}

}  // namespace dash::test

namespace dash::test {

/// Smallest signed distance between the bodies of robot ra at qa and those of robot rb at qb (exact).
inline double bodiesSignedDistance(const CollisionWorld& world, int ra, const JointVector& qa, int rb,
                                   const JointVector& qb) {
  CollisionContext context(world);
  auto posed = [&](int r, const JointVector& q) {
    const RobotGeometry& g = world.robot(r);
    std::vector<Pose> frames(g.bodies.size());
    bodyFrames(*g.model, g.robot->X_WB, q, frames);
    for (std::size_t b = 0; b < frames.size(); ++b) frames[b] = frames[b] * g.bodies[b].X_FG;
    return frames;
  };
  const auto fa = posed(ra, qa);
  const auto fb = posed(rb, qb);
  double best = 1e9;
  for (std::size_t i = 0; i < fa.size(); ++i) {
    for (std::size_t k = 0; k < fb.size(); ++k) {
      best = std::min(best, signedDistance(context, *world.robot(ra).bodies[i].shape, fa[i],
                                           *world.robot(rb).bodies[k].shape, fb[k]));
    }
  }
  return best;
}

/// The IK solution for X_WT nearest to `near` (every component), for robot r.
inline JointVector nearestIk(const Scene& scene, int r, const Pose& X_WT, const JointVector& near) {
  const SceneRobot& robot = scene.robots[static_cast<std::size_t>(r)];
  const auto solutions = inverseKinematics(*robot.model, robot.X_WB, X_WT);
  JointVector best = near;
  double best_d = 1e9;
  for (const JointVector& q : solutions) {
    const double d = (q - near).norm();
    if (d < best_d) {
      best_d = d;
      best = q;
    }
  }
  return best;
}

/// Two UR5e facing each other across x hand a 1 x 4 x 4 cm plate over at c = (0.5, 0, 0.3). ur5e_0
/// holds it from the start, 3 cm inside its fingers (its home grasps it; fingers along y); ur5e_1 comes in along -x with its fingers
/// along z, grasps, ur5e_0 lets go, ur5e_1 puts it down where it is (a surface at z = 0.28) and backs
/// out. ur5e_1's closing point is chosen so that the grippers end `overlap` deep in each other
/// (negative: that far apart).
struct HandoverCase {
  Scene scene;
  Plan plan;
  double reached = 0.0;  ///< the signed distance of the two robots at the closing point
};

inline HandoverCase urHandover(double overlap) {
  Scene scene = exampleScene();
  scene.name = "ur-handover";
  scene.end_at_home = false;
  scene.obstacles.clear();
  scene.tasks.clear();
  SceneRobot second = scene.robots.front();
  second.id = "ur5e_1";
  second.X_WB = yaw(Vec3(1.0, 0.0, 0.0), std::numbers::pi);
  scene.robots.push_back(second);
  const Vec3 c(0.5, 0.0, 0.3);
  SceneObject& cube = scene.objects.front();
  cube.shape.size = Vec3(0.01, 0.04, 0.04);
  cube.X_WO_start = makePose(c);
  cube.X_WO_goal.reset();
  scene.surfaces.clear();
  scene.surfaces.push_back({"stand_top", 0.28,
                            {Eigen::Vector2d(0.45, -0.05), Eigen::Vector2d(0.55, -0.05), Eigen::Vector2d(0.55, 0.05),
                             Eigen::Vector2d(0.45, 0.05)}});
  Eigen::Matrix3d R_a;  // tool z along +x, fingers (flange x) along y
  R_a.col(0) = Vec3::UnitY();
  R_a.col(1) = Vec3::UnitZ();
  R_a.col(2) = Vec3::UnitX();
  Eigen::Matrix3d R_b;  // tool z along -x, fingers along z
  R_b.col(0) = Vec3::UnitZ();
  R_b.col(1) = Vec3::UnitY();
  R_b.col(2) = -Vec3::UnitX();
  const JointVector seed = scene.robots[0].home;
  const JointVector q_a = nearestIk(scene, 0, makePose(c + Vec3(0.03, 0, 0), Quat(R_a)), seed);
  auto b_at = [&](double dx) { return nearestIk(scene, 1, makePose(c + Vec3(dx, 0, 0), Quat(R_b)), seed); };
  const JointVector q_b_out = b_at(0.06);
  scene.robots[0].home = q_a;
  scene.robots[1].home = q_b_out;
  const CollisionWorld world(scene);
  // Bisection on ur5e_1's TCP offset: the signed distance falls as it comes closer.
  double lo = -0.035;  // deep
  double hi = 0.06;    // apart
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    const JointVector q_b = nearestIk(scene, 1, makePose(c + Vec3(mid, 0, 0), Quat(R_b)), q_b_out);
    (bodiesSignedDistance(world, 0, q_a, 1, q_b) > -overlap ? hi : lo) = mid;
  }
  const JointVector q_b_in = nearestIk(scene, 1, makePose(c + Vec3(hi, 0, 0), Quat(R_b)), q_b_out);
  HandoverCase out{scene, {}, bodiesSignedDistance(world, 0, q_a, 1, q_b_in)};
  Plan& plan = out.plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const auto& names = scene.robots[0].model->joint_names;
  plan.robots.push_back({"ur5e_0", names, {point(0.0, q_a), point(4.0, q_a)}});
  plan.robots.push_back({"ur5e_1", names, {point(0.0, q_b_out), point(1.0, q_b_in), point(2.0, q_b_in), point(3.0, q_b_out)}});
  auto attach = [&](int r, const JointVector& q) {
    const SceneRobot& robot = scene.robots[static_cast<std::size_t>(r)];
    return Pose(forwardKinematics(*robot.model, robot.X_WB, q).X_WT.inverse() * cube.X_WO_start);
  };
  plan.events.push_back({PlanEvent::Type::kGrasp, 0.0, "ur5e_0", cube.id, attach(0, q_a), -1});
  plan.events.push_back({PlanEvent::Type::kGrasp, 1.0, "ur5e_1", cube.id, attach(1, q_b_in), -1});
  plan.events.push_back({PlanEvent::Type::kRelease, 1.5, "ur5e_0", cube.id, Pose::Identity(), -1});
  plan.events.push_back({PlanEvent::Type::kRelease, 2.0, "ur5e_1", cube.id, Pose::Identity(), -1});
  plan.makespan = 4.0;
  return out;
}

}  // namespace dash::test

namespace dash::test {

/// The example UR5e panning from -0.2 to +0.2 rad about its home, past a wall (a 2 x 30 x 8 cm box
/// at the forearm's height, facing it at the middle of the pan) that the forearm's capsule reaches
/// `overlap` deep at the middle (negative: stays that far away). Both plan points are clear.
struct ForearmCase {
  Scene scene;
  Plan plan;
  double reached = 0.0;  ///< the smallest signed distance of forearm and wall found on 1001 samples
};

inline ForearmCase forearmWall(double overlap) {
  Scene scene = exampleScene();
  scene.name = "forearm-wall";
  scene.tasks.clear();
  for (SceneObject& o : scene.objects) o.X_WO_goal.reset();
  scene.end_at_home = false;
  const SceneRobot& robot = scene.robots[0];
  const JointVector mid = robot.home;
  JointVector q_a = mid;
  JointVector q_b = mid;
  q_a[0] -= 0.08;
  q_b[0] += 0.08;
  int forearm = 0;
  while (robot.model->bodies[static_cast<std::size_t>(forearm)].name != "forearm") ++forearm;
  std::vector<Pose> frames(robot.model->bodies.size());
  bodyFrames(*robot.model, robot.X_WB, mid, frames);
  const CollisionBody& body = robot.model->bodies[static_cast<std::size_t>(forearm)];
  // The forearm's outer end (the wrist end, frame 3's origin: its cap reaches 5 mm past wrist_1).
  const Vec3 m = frames[static_cast<std::size_t>(forearm)] * body.capsule.b;
  Vec3 n = m - robot.X_WB.translation();
  n.z() = 0.0;
  n.normalize();
  const Quat facing(Eigen::AngleAxisd(std::atan2(n.y(), n.x()), Vec3::UnitZ()));
  auto wallAt = [&](double face) {  // face: the wall's near face, along n from the base axis
    const Vec3 centre = robot.X_WB.translation() + (face + 0.01) * n;
    return makePose(Vec3(centre.x(), centre.y(), m.z()), facing);
  };
  SceneObstacle wall;
  wall.id = "wall";
  wall.shape.size = Vec3(0.02, 0.04, 0.08);
  scene.obstacles.push_back(wall);
  auto closest = [&](double face) {
    scene.obstacles.back().X_WO = wallAt(face);
    const CollisionWorld world(scene);
    CollisionContext context(world);
    const ObstacleGeometry& o = world.obstacles().back();
    double best = 1e9;
    for (int k = 0; k <= 1000; ++k) {
      const JointVector q = q_a + (q_b - q_a) * (static_cast<double>(k) / 1000.0);
      bodyFrames(*robot.model, robot.X_WB, q, frames);
      const auto& g = world.robot(0).bodies[static_cast<std::size_t>(forearm)];
      best = std::min(best, signedDistance(context, *g.shape, frames[static_cast<std::size_t>(forearm)] * g.X_FG,
                                           *o.shape, o.X_WO));
    }
    return best;
  };
  double lo = 0.0;  // deep
  double hi = 2.0;  // apart
  for (int i = 0; i < 40; ++i) {
    const double face = 0.5 * (lo + hi);
    (closest(face) > -overlap ? hi : lo) = face;
  }
  ForearmCase out{scene, {}, closest(hi)};
  out.scene.robots[0].home = q_a;
  out.plan.scene = scene.name;
  out.plan.planner = "test";
  out.plan.robots.push_back({robot.id, robot.model->joint_names, {point(0.0, q_a), point(1.0, q_b)}});
  out.plan.makespan = 1.0;
  return out;
}

}  // namespace dash::test

namespace dash::test {

/// The handover's two UR5e (urHandover: ur5e_0 holds the plate with its fingers along y, its tool
/// along +x), but ur5e_1 (fingers along z) comes in off to the side: on a straight joint-space
/// segment its upper fingertip slides diagonally, in x and y, past the outer corner of ur5e_0's +y
/// fingertip and cuts into it `overlap` deep at the deepest instant (negative: passes that far away).
/// Both plan points are clear, and the deepest instant falls halfway between two of the 1 cm
/// sampler's instants: fingers are boxes, so the cut lasts well under a millimetre of travel.
struct FingertipCase {
  Scene scene;
  Plan plan;
  double reached = 0.0;     ///< the fingers' smallest signed distance along the segment
  double u_deepest = 0.0;   ///< where, as a fraction of the segment (t = 1 + u)
  int sampler_steps = 0;    ///< the sampled check's steps over the segment
  double at_samples = 0.0;  ///< the fingers' distance at the sampler's instants either side
};

/// urFingertipClip's geometry: ur5e_0 still at q_a, ur5e_1's tool posed along the corner's lines.
class FingertipPair {
 public:
  FingertipPair(const Scene& scene, const JointVector& q_a) : scene_(scene), world_(scene), context_(world_) {
    f0_.resize(world_.robot(0).bodies.size());
    f1_.resize(world_.robot(1).bodies.size());
    bodyFrames(*world_.robot(0).model, scene.robots[0].X_WB, q_a, f0_);
    R_b_.col(0) = Vec3::UnitZ();  // tool z along -x, fingers along z
    R_b_.col(1) = Vec3::UnitY();
    R_b_.col(2) = -Vec3::UnitX();
  }
  const CollisionWorld& world() const { return world_; }

  /// The smallest signed distance of the four finger pairs with ur5e_1 at q.
  double fingers(const JointVector& q) {
    const RobotGeometry& g0 = world_.robot(0);
    const RobotGeometry& g1 = world_.robot(1);
    bodyFrames(*g1.model, scene_.robots[1].X_WB, q, f1_);
    double best = 1e9;
    for (std::size_t i = 0; i < g0.bodies.size(); ++i) {
      if (g0.model->bodies[i].name.rfind("finger", 0) != 0) continue;
      for (std::size_t k = 0; k < g1.bodies.size(); ++k) {
        if (g1.model->bodies[k].name.rfind("finger", 0) != 0) continue;
        best = std::min(best, signedDistance(context_, *g0.bodies[i].shape, f0_[i] * g0.bodies[i].X_FG,
                                             *g1.bodies[k].shape, f1_[k] * g1.bodies[k].X_FG));
      }
    }
    return best;
  }
  /// ur5e_1 with its tool s along the way in and e into the corner from the touching pose.
  JointVector at(double s, double e) const {
    // ur5e_0's +y finger spans x in [0.488, 0.538], y in [0.025, 0.036]; ur5e_1's upper finger spans
    // x in [T.x - 0.008, T.x + 0.042], y within 0.0105 of T.y, z in [T.z + 0.025, T.z + 0.036]. With
    // T = kTouch its tip's -y edge lies on the other's outer tip edge.
    const Vec3 kTouch(0.546, 0.0465, 0.2695);
    const Vec3 in = Vec3(-1.0, 1.0, 0.0).normalized();      // the way it travels: in along -x, out along +y
    const Vec3 deeper = Vec3(-1.0, -1.0, 0.0).normalized();  // into the corner
    return nearestIk(scene_, 1, makePose(kTouch + s * in + e * deeper, Quat(R_b_)), scene_.robots[1].home);
  }
  /// The deepest cut along the segment s = -before .. after at `offset` into the corner, and where it is
  /// (u_min, a fraction of the segment): a ternary search, the cut being one tent.
  double deepest(double before, double after, double offset, double& u_min) {
    const JointVector q0 = at(-before, offset);
    const JointVector q1 = at(after, offset);
    double lo = 0.0;
    double hi = 1.0;
    for (int i = 0; i < 60; ++i) {
      const double m1 = lo + (hi - lo) / 3.0;
      const double m2 = hi - (hi - lo) / 3.0;
      if (fingers(q0 + m1 * (q1 - q0)) < fingers(q0 + m2 * (q1 - q0))) {
        hi = m2;
      } else {
        lo = m1;
      }
    }
    u_min = 0.5 * (lo + hi);
    return fingers(q0 + u_min * (q1 - q0));
  }

 private:
  const Scene& scene_;
  CollisionWorld world_;
  CollisionContext context_;
  Eigen::Matrix3d R_b_;
  std::vector<Pose> f0_, f1_;
};

/// urFingertipClip's plan: ur5e_0 holds the plate at q_a, ur5e_1 goes q0 -> q1 over [1, 2] s.
inline Plan fingertipPlan(const Scene& scene, const JointVector& q_a, const JointVector& q0, const JointVector& q1) {
  Plan plan;
  plan.scene = scene.name;
  plan.planner = "test";
  const auto& names = scene.robots[0].model->joint_names;
  plan.robots.push_back({"ur5e_0", names, {point(0.0, q_a), point(3.0, q_a)}});
  plan.robots.push_back({"ur5e_1", names, {point(0.0, q0), point(1.0, q0), point(2.0, q1), point(3.0, q1)}});
  const SceneObject& plate = scene.objects.front();
  const SceneRobot& r0 = scene.robots[0];
  plan.events.push_back({PlanEvent::Type::kGrasp, 0.0, "ur5e_0", plate.id,
                         Pose(forwardKinematics(*r0.model, r0.X_WB, q_a).X_WT.inverse() * plate.X_WO_start), -1});
  plan.events.push_back({PlanEvent::Type::kRelease, 3.0, "ur5e_0", plate.id, Pose::Identity(), -1});
  plan.makespan = 3.0;
  return plan;
}

inline FingertipCase urFingertipClip(double overlap) {
  HandoverCase base = urHandover(0.0);  // its scene: plate at c, ur5e_0 holding it at home
  Scene scene = base.scene;
  scene.name = "ur-fingertip-clip";
  const JointVector q_a = scene.robots[0].home;
  FingertipPair pair(scene, q_a);
  // The segment runs from s = -before to s = +after (2 cm in all); `split` puts the corner halfway
  // between two sampler instants.
  double split = 0.5;
  double e = overlap * std::sqrt(2.0);
  FingertipCase out;
  for (int round = 0; round < 4; ++round) {
    const double before = 0.02 * split;
    const double after = 0.02 - before;
    // Bisection on the offset: the cut deepens as the path moves into the corner.
    double lo = e - 0.002;
    double hi = e + 0.002;
    double u_min = 0.5;
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (pair.deepest(before, after, mid, u_min) > -overlap ? lo : hi) = mid;
    }
    e = hi;
    out.reached = pair.deepest(before, after, e, u_min);
    out.u_deepest = u_min;
    const JointVector q0 = pair.at(-before, e);
    const JointVector q1 = pair.at(after, e);
    out.sampler_steps = segmentSteps(pair.world(), 1, q0, q1, HeldObject{});
    const int n = out.sampler_steps;
    const double target = (std::floor(u_min * n) + 0.5) / n;  // halfway between two samples
    out.at_samples = std::min(pair.fingers(q0 + std::floor(u_min * n) / n * (q1 - q0)),
                              pair.fingers(q0 + std::ceil(u_min * n) / n * (q1 - q0)));
    if (std::abs(u_min - target) < 0.02 / n) break;
    split = std::clamp(split + (target - u_min), 0.1, 0.9);
  }
  const double before = 0.02 * split;
  const JointVector q0 = pair.at(-before, e);
  const JointVector q1 = pair.at(0.02 - before, e);
  scene.robots[1].home = q0;
  out.scene = scene;
  out.plan = fingertipPlan(scene, q_a, q0, q1);
  return out;
}

}  // namespace dash::test
