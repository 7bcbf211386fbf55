#pragma once
// A planning scene in the dashbench.scene/1 format (docs/formats.md): robots with their
// mounting poses and home configurations, static obstacles, support surfaces, movable objects and extra
// tasks. Immutable once loaded and shared by const reference; the robot models it points to are kept
// alive by the RobotLibrary it holds.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <Eigen/Core>

#include "engine/geometry/pose.h"
#include "engine/geometry/shapes.h"
#include "engine/robots/joint_vector.h"
#include "engine/robots/robot_model.h"

namespace dash {

inline constexpr const char* kSceneFormat = "dashbench.scene/1";

/// One generator parameter value: a number or a string, as written in the file.
using SceneParamValue = std::variant<double, std::string>;

/// Which generator made the scene and how (for reproducing it).
struct SceneGenerator {
  std::string name;
  std::vector<std::pair<std::string, SceneParamValue>> params;  ///< in file order
  std::uint64_t seed = 0;
};

struct SceneRobot {
  std::string id;
  std::string model_name;
  const RobotModel* model = nullptr;  ///< owned by Scene::library
  Pose X_WB = Pose::Identity();       ///< mounting pose of the robot's frame 0
  JointVector home;
  std::vector<std::string> capabilities;  ///< "grasp", "inspect", ...

  bool hasCapability(const std::string& capability) const;
};

struct SceneObstacle {
  std::string id;
  BoxShape shape;
  Pose X_WO = Pose::Identity();
};

/// A horizontal support polygon at height z (x, y in the world frame).
struct SceneSurface {
  std::string id;
  double z = 0.0;
  std::vector<Eigen::Vector2d> polygon;
};

struct SceneObject {
  std::string id;
  BoxShape shape;
  Pose X_WO_start = Pose::Identity();
  std::optional<Pose> X_WO_goal;
  bool fixed = false;
};

/// An extra goal beyond object goals. Only "inspect" exists today.
struct SceneTask {
  enum class Type { kInspect };
  Type type = Type::kInspect;
  std::string target;                          ///< object id
  int target_object = -1;                      ///< index into Scene::objects
  Pose X_WT = Pose::Identity();                ///< TCP pose to reach (within 5 mm)
  std::optional<std::string> requires_removed;  ///< object id that must be away from its start
  int requires_removed_object = -1;            ///< index into Scene::objects, -1 if none
  std::string capability;
};

struct Scene {
  std::string name;
  std::optional<SceneGenerator> generator;
  std::vector<SceneRobot> robots;
  std::vector<SceneObstacle> obstacles;
  std::vector<SceneSurface> surfaces;
  std::vector<SceneObject> objects;
  std::vector<SceneTask> tasks;
  bool end_at_home = true;
  std::shared_ptr<const RobotLibrary> library;  ///< keeps every SceneRobot::model alive

  int robotIndex(const std::string& id) const;     ///< -1 if absent
  int objectIndex(const std::string& id) const;    ///< -1 if absent
  int obstacleIndex(const std::string& id) const;  ///< -1 if absent
};

}  // namespace dash
