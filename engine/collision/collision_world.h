#pragma once
// The collision geometry of a scene, built once and shared by const& between threads. Per-thread
// scratch lives in CollisionContext (the Pinocchio model/data split); queries are free functions in
// collision_queries.h, segment_queries.h and distance_queries.h.
//
// Geometry rules (formats.md): robot bodies are exactly the model's capsules and boxes; obstacles and
// objects are exact boxes. A contact tolerance (kObjectContactTolerance, 1 mm) applies only where
// contact is meant:
//  - an object resting on its support: resting objects are checked against obstacles and each other
//    with their contact box (shrunk by the tolerance on every face);
//  - a gripper and the object it grasps: gripper bodies meet resting objects' contact boxes (the
//    gantry tool touches the top face it grasps; a gripper about to grasp or just released an object
//    touches it), and never the object they hold;
//  - a held object and the surface it is picked from or put down on: against obstacles and resting
//    objects a held object is its exact box with its lowest face (the one whose outward normal points
//    most nearly down) raised by kHeldBottomTolerance (0.1 mm, less than the resting tolerance: the
//    planners put objects down and lift them off along straight TCP lines, cartesian_path.h), so it
//    may sit on a shelf board but not enter it from the side or from below, nor sink into it by more.
// Everything else, a carried object against another robot or its own arm included, is exact.
//
// Clearance (CollisionWorldOptions::clearance, the planners' margin): robot bodies and held objects are
// grown so that every pair they form keeps at least that distance, except where contact is meant (the
// gripper bodies against resting objects, the held object's lowest face against static geometry).
// Against obstacles and resting objects a part is grown by the whole clearance; against another
// robot's parts (or its own, in self pairs) each side by half of it.
//
// Mounting: no exemption for a robot's base against the surface it stands on. The shipped models keep
// clear of their mounting plane (the UR5e base capsule starts 5 mm above frame 0; the gantry's lowest
// point is 0.1 m up), so a robot mounted on a table top does not touch the table. A scene that sinks a
// base into an obstacle is reported as a collision.
#include <array>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "engine/collision/link_cover.h"
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
/// m: how far a held object's lowest face may reach into the surface it is picked from or put down on.
inline constexpr double kHeldBottomTolerance = 1e-4;
/// Planners: a gripper body of an empty hand may touch the resting object nearest its TCP, if the TCP is
/// within this of its box (a gripper on its approach line, at a grasp or just after a release); no other
/// one, and none while the hand holds an object.
inline constexpr double kGraspReach = 0.02;

/// The planners' default clearance (LazyDashParams, DashParams): a few millimetres, so that what they
/// check at discrete configurations passes the certified validator at zero clearance.
inline constexpr double kDefaultPlanningClearance = 0.002;

struct CollisionWorldOptions {
  /// Metres every robot-side pair keeps apart, except where contact is meant (see above). The plan
  /// validator checks at 0 (or at `dashbench validate --clearance`); planners plan with a few mm.
  double clearance = 0.0;
  /// Whether the queries may clear pairs by the conservative covers before the exact check
  /// (cover_check.h; same answers, faster). The plan validator builds its worlds without them, so
  /// that its verdicts rest on the exact geometry alone.
  bool cover = true;
};

using ShapePtr = std::shared_ptr<const fcl::CollisionGeometry<double>>;

/// One robot body's collision geometry, rigid in its body frame F (see kinematics.h, bodyFrames).
struct BodyGeometry {
  ShapePtr shape;               ///< exact
  ShapePtr shape_vs_static;     ///< grown by the clearance: against obstacles and resting objects
  ShapePtr shape_vs_robot;      ///< grown by half the clearance: against robot bodies and held objects
  Pose X_FG = Pose::Identity();  ///< the FCL shape's frame in F
  bool is_capsule = true;
  Vec3 a = Vec3::Zero();          ///< capsule segment in F
  Vec3 b = Vec3::Zero();
  double radius = 0.0;
  Vec3 center = Vec3::Zero();     ///< box centre in F
  Vec3 half_extents = Vec3::Zero();
  bool is_gripper = false;
  /// Gripper bodies: the TCP in F (rigid: a gripper body moves with the tool). Identity otherwise.
  Pose X_FT = Pose::Identity();
  double extent = 0.0;            ///< farthest point of the body from the origin of F
  CoverCapsule cover;             ///< in F: contains the grown shapes (link_cover.h)
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
  Vec3 half_extents = Vec3::Zero();
  Aabb aabb;
};

struct ObjectGeometry {
  ShapePtr shape;                     ///< exact box
  Vec3 half_extents = Vec3::Zero();   ///< of the exact box
  ShapePtr contact_shape;             ///< shrunk by the contact tolerance: resting contact
  Vec3 contact_half_extents = Vec3::Zero();
  /// Held, against obstacles and resting objects, when axis k of the object points most nearly up or
  /// down: the exact box grown by the clearance except along that axis, where it spans from the lowest
  /// face raised by the tolerance to the highest face raised by the clearance (heldStaticShape).
  std::array<ShapePtr, 3> held_vs_static;
  /// Held in transit (HeldObject::in_transit), against obstacles and resting objects: the exact box
  /// grown by the clearance on every face.
  ShapePtr held_in_transit;
  ShapePtr held_vs_robot;             ///< held, against robot parts: grown by half the clearance
  double bottom_tolerance = 0.0;      ///< the tolerance at the lowest face (less for tiny objects)
  /// Held, in the object frame: contains every held shape above (each lies in the exact box grown by
  /// the clearance; link_cover.h).
  CoverCapsule held_cover;
};

class CollisionWorld {
 public:
  /// Builds the geometry; `scene` must outlive the world.
  explicit CollisionWorld(const Scene& scene, CollisionWorldOptions options = {});

  const Scene& scene() const { return *scene_; }
  double clearance() const { return options_.clearance; }
  bool usesCover() const { return options_.cover; }
  int robotCount() const { return static_cast<int>(robots_.size()); }
  int objectCount() const { return static_cast<int>(objects_.size()); }
  const RobotGeometry& robot(int r) const { return robots_[static_cast<std::size_t>(r)]; }
  const std::vector<ObstacleGeometry>& obstacles() const { return obstacles_; }
  const ObjectGeometry& object(int j) const { return objects_[static_cast<std::size_t>(j)]; }
  /// 0 .. obstacles().size()-1, for candidate lists.
  const std::vector<int>& allObstacles() const { return all_obstacles_; }

 private:
  const Scene* scene_;
  CollisionWorldOptions options_;
  std::vector<RobotGeometry> robots_;
  std::vector<ObstacleGeometry> obstacles_;
  std::vector<ObjectGeometry> objects_;
  std::vector<int> all_obstacles_;
};

/// World box of a box shape (full half extents `half`) at pose X.
Aabb boxAabb(const Pose& X, const Vec3& half);

/// A held object's shape against static geometry at world pose X_WO, and that shape's world pose.
struct PosedShape {
  const fcl::CollisionGeometry<double>* shape = nullptr;
  Pose X_WS = Pose::Identity();
};
PosedShape heldStaticShape(const CollisionWorld& world, int object, const Pose& X_WO);

}  // namespace dash
