#pragma once
// A robot model in the dashbench.robot/1 format (data/robots/*.json): kinematics, limits and
// collision bodies. Immutable once loaded and shared by const reference (Pinocchio's model/data split).
#include <array>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/geometry/shapes.h"
#include "engine/robots/joint_vector.h"

namespace dash {

enum class KinematicsKind { kUrDh, kGantry };

/// Standard DH parameters of a 6-axis UR arm: T_(i-1,i) = Rz(q_i) Tz(d_i) Tx(a_i) Rx(alpha_i).
struct DhParameters {
  std::array<double, 6> a{};
  std::array<double, 6> d{};
  std::array<double, 6> alpha{};
  Pose X_FT = Pose::Identity();  ///< TCP in the flange frame.
  /// cos/sin of alpha, cached for the FK hot path (values within 1e-15 of 0 or +-1 are snapped).
  /// parseRobotModel fills them; call updateDerived() after editing alpha by hand.
  std::array<double, 6> cos_alpha{1.0, 1.0, 1.0, 1.0, 1.0, 1.0};
  std::array<double, 6> sin_alpha{};
  void updateDerived();
};

/// Cartesian gantry q = [x, y, z]; see gantry3.json for the frame conventions.
struct GantryParameters {
  double beam_height = 0.0;
  double ram_to_tcp = 0.0;
};

struct JointLimits {
  JointVector position_min;
  JointVector position_max;
  JointVector velocity_max;
};

/// One rigid collision body. For a UR arm it is rigid in DH frame `frame` (0 = base .. 6 = flange).
/// For a gantry it is a box in frame 0 whose centre moves with the axes flagged in `moves`; its body
/// frame (bodyFrames() in kinematics.h) sits at that moved centre with the base's orientation, so
/// box_center is zero and the file's centre (at q = 0) is kept in gantry_base_center. Either way the
/// shape's world pose is bodyFrames()[i] * Translation(box_center).
/// is_gripper: the body is rigid with the TCP (UR: frame 6, the flange-mounted gripper; gantry:
/// moves with x, y and z), unless the file's optional "gripper": true/false says otherwise.
struct CollisionBody {
  enum class Kind { kCapsule, kBox };
  std::string name;
  Kind kind = Kind::kCapsule;
  int frame = 0;
  CapsuleShape capsule;          ///< when kind == kCapsule (a, b in the body frame)
  Vec3 box_center = Vec3::Zero();  ///< when kind == kBox, in the body frame
  Vec3 box_half_extents = Vec3::Zero();
  std::array<bool, 3> moves{false, false, false};  ///< gantry only: follows x, y, z
  Vec3 gantry_base_center = Vec3::Zero();  ///< gantry only: box centre in frame 0 at q = 0
  bool is_gripper = false;  ///< never counts against the object this robot holds
};

class RobotModel {
 public:
  std::string name;         ///< "ur5e", "gantry3"
  std::string description;
  KinematicsKind kinematics = KinematicsKind::kUrDh;
  std::vector<std::string> joint_names;
  JointLimits limits;
  DhParameters dh;          ///< when kinematics == kUrDh
  GantryParameters gantry;  ///< when kinematics == kGantry
  std::vector<CollisionBody> bodies;
  std::vector<std::pair<int, int>> self_collision_pairs;  ///< indices into bodies

  int dof() const { return static_cast<int>(joint_names.size()); }
  int bodyIndex(const std::string& body_name) const;  ///< -1 if absent
  bool withinLimits(const JointVector& q, double tolerance = 1e-9) const;
};

/// Parses a dashbench.robot/1 document. Throws InputError naming the field on malformed input.
RobotModel parseRobotModel(const std::string& json_text, const std::string& source_name);
/// Loads data/robots/<model>.json style files.
RobotModel loadRobotModel(const std::string& path);

/// The models a scene may reference, by name. Loaded once, then immutable and shared.
class RobotLibrary {
 public:
  /// Loads every *.json in the folder (default: <data>/robots).
  static std::shared_ptr<const RobotLibrary> loadDirectory(const std::string& folder);
  static std::shared_ptr<const RobotLibrary> loadDefault();

  const RobotModel* find(const std::string& name) const;  ///< nullptr if unknown
  const RobotModel& get(const std::string& name) const;   ///< throws InputError if unknown
  std::vector<std::string> names() const;

 private:
  std::vector<std::shared_ptr<const RobotModel>> models_;
};

}  // namespace dash
