#pragma once
// Small scenes built in code for the collision tests.
#include <cmath>
#include <memory>
#include <string>

#include "engine/robots/kinematics.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene.h"
#include "engine/scene/scene_json.h"
#include "tests/common/examples.h"
#include "tests/common/robot_library.h"

namespace dash::test {

inline Scene exampleScene() { return loadScene(exampleScenePath(), library()); }

inline Pose yawPose(double x, double y, double z, double yaw = 0.0) {
  return makePose(Vec3(x, y, z), Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())));
}

inline JointVector urHome() {
  JointVector q(6);
  q << 0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0;
  return q;
}

inline JointVector joints(std::initializer_list<double> values) {
  JointVector q(static_cast<Eigen::Index>(values.size()));
  Eigen::Index i = 0;
  for (double v : values) q[i++] = v;
  return q;
}

/// An empty scene (no table) with the library set.
inline Scene emptyScene(const std::string& name = "test") {
  Scene s;
  s.name = name;
  s.library = library();
  return s;
}

inline void addUr(Scene& s, const std::string& id, const Pose& X_WB, const JointVector& home = urHome()) {
  SceneRobot r;
  r.id = id;
  r.model_name = "ur5e";
  r.model = s.library->find("ur5e");
  r.X_WB = X_WB;
  r.home = home;
  r.capabilities = {"grasp"};
  s.robots.push_back(r);
}

inline void addObstacle(Scene& s, const std::string& id, const Vec3& size, const Pose& X_WO) {
  s.obstacles.push_back(SceneObstacle{.id = id, .shape = BoxShape{size}, .X_WO = X_WO});
}

/// The example's table: 3 m square, top face at z = 0.
inline void addTable(Scene& s) {
  addObstacle(s, "table", Vec3(3.0, 3.0, 0.05), makePose(Vec3(0, 0, -0.025)));
  s.surfaces.push_back(SceneSurface{.id = "table_top", .z = 0.0, .polygon = {{-1.5, -1.5}, {1.5, -1.5}, {1.5, 1.5}, {-1.5, 1.5}}});
}

inline void addCube(Scene& s, const std::string& id, double edge, const Pose& X_WO) {
  s.objects.push_back(SceneObject{.id = id, .shape = BoxShape{Vec3::Constant(edge)}, .X_WO_start = X_WO});
}

/// Tool pointing straight down (TCP z = world -z).
inline Pose toolDown(const Vec3& p) {
  return makePose(p, Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX())));
}

}  // namespace dash::test
