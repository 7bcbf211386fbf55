#pragma once
// The collision geometry of a scene, built once and shared by const& between threads. Per-thread
// scratch lives in CollisionContext (the Pinocchio model/data split); queries are free functions in
// collision_queries.h, segment_queries.h and distance_queries.h.
//
// Geometry rules (formats.md): robot bodies are exactly the model's capsules and boxes; obstacles are
// exact boxes. Objects are checked with a contact tolerance: each object's collision box is its box
// shrunk by kObjectContactTolerance on every face. So an object resting on a surface or on another
// object, or touched by the gantry tool that grasps it at its top face, is not a collision, while any
// penetration deeper than 1 mm is. Robot geometry is never shrunk.
//
// Mounting: no exemption for a robot's base against the surface it stands on. The shipped models keep
// clear of their mounting plane (the UR5e base capsule starts 5 mm above frame 0; the gantry's lowest
// point is 0.1 m up), so a robot mounted on a table top does not touch the table. A scene that sinks a
// base into an obstacle is reported as a collision.
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "engine/geometry/pose.h"
#include "engine/robots/joint_vector.h"
#include "engine/scene/scene.h"

namespace fcl {
template <typename S>
class CollisionGeometry;
}  // namespace fcl

namespace dash {

using Aabb = Eigen::AlignedBox3d;

inline constexpr double kObjectContactTolerance = 1e-3;

/// One robot body's collision geometry, rigid in its body frame F (see kinematics.h, bodyFrames).
struct BodyGeometry {
  std::shared_ptr<const fcl::CollisionGeometry<double>> shape;
  Pose X_FG = Pose::Identity();  ///< the FCL shape's frame in F
  bool is_capsule = true;
  Vec3 a = Vec3::Zero();          ///< capsule segment in F
  Vec3 b = Vec3::Zero();
  double radius = 0.0;
  Vec3 center = Vec3::Zero();     ///< box centre in F
  Vec3 half_extents = Vec3::Zero();
  bool is_gripper = false;
  double extent = 0.0;            ///< farthest point of the body from the origin of F
};

struct RobotGeometry {
  const SceneRobot* robot = nullptr;
  const RobotModel* model = nullptr;
  std::vector<BodyGeometry> bodies;  ///< model->bodies order
  /// World box holding every body at every configuration within the limits (held objects excluded).
  Aabb reach;
  /// Obstacles whose box meets `reach`: the only ones the robot's bodies are tested against.
  std::vector<int> nearby_obstacles;
  /// Bodies that are not gripper bodies: what the robot's own held object is checked against.
  std::vector<int> non_gripper_bodies;
  /// Segment resolution: body_lever[b][i] bounds how far any point of body b moves per unit of joint i
  /// (for a revolute joint the largest distance from its axis; 1 for a prismatic joint that moves the
  /// body; 0 if the body does not follow joint i). Holds at every configuration.
  std::vector<JointVector> body_lever;
  JointVector tcp_lever;  ///< the same bound for the TCP origin
};

struct ObstacleGeometry {
  std::shared_ptr<const fcl::CollisionGeometry<double>> shape;
  Pose X_WO = Pose::Identity();
  Aabb aabb;
};

struct ObjectGeometry {
  std::shared_ptr<const fcl::CollisionGeometry<double>> shape;  ///< the contact (shrunk) box
  Vec3 half_extents = Vec3::Zero();  ///< of the contact box
};

class CollisionWorld {
 public:
  /// Builds the geometry; `scene` must outlive the world.
  explicit CollisionWorld(const Scene& scene);

  const Scene& scene() const { return *scene_; }
  int robotCount() const { return static_cast<int>(robots_.size()); }
  int objectCount() const { return static_cast<int>(objects_.size()); }
  const RobotGeometry& robot(int r) const { return robots_[static_cast<std::size_t>(r)]; }
  const std::vector<ObstacleGeometry>& obstacles() const { return obstacles_; }
  const ObjectGeometry& object(int j) const { return objects_[static_cast<std::size_t>(j)]; }
  /// 0 .. obstacles().size()-1, for candidate lists.
  const std::vector<int>& allObstacles() const { return all_obstacles_; }

 private:
  const Scene* scene_;
  std::vector<RobotGeometry> robots_;
  std::vector<ObstacleGeometry> obstacles_;
  std::vector<ObjectGeometry> objects_;
  std::vector<int> all_obstacles_;
};

/// World box of a box shape (full half extents `half`) at pose X.
Aabb boxAabb(const Pose& X, const Vec3& half);

}  // namespace dash
