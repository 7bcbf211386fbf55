#pragma once
// Assembles a Scene for a generator. Every length is rounded to a micrometre and every yaw quaternion
// to 1e-9 as it is added, so the written numbers are short and do not carry the last bits of a
// platform's sin/cos. Obstacles and objects here are upright boxes turned about the world z axis.
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/scene/scene.h"

namespace dash {

/// Rounds a length to 1e-6 m.
double roundLength(double x);
/// Upright pose: position (rounded) and a rotation of `yaw` about world z (quaternion rounded).
Pose yawPose(const Vec3& p, double yaw);
/// A point of the plane, rotated by yaw about the origin.
Eigen::Vector2d rotate2(const Eigen::Vector2d& v, double yaw);

class SceneBuilder {
 public:
  SceneBuilder(std::shared_ptr<const RobotLibrary> library, std::string name, SceneGenerator generator);

  void addRobot(const std::string& id, const std::string& model, const Vec3& p, double yaw,
                const std::vector<double>& home, std::vector<std::string> capabilities);
  /// A box obstacle of full size `size`, centred at `center`, turned by yaw.
  void addBox(const std::string& id, const Vec3& size, const Vec3& center, double yaw = 0.0);
  /// A surface given by its corners (counter-clockwise), at height z.
  void addSurface(const std::string& id, double z, const std::vector<Eigen::Vector2d>& polygon);
  /// A rectangular surface of size (sx, sy), centred at (cx, cy), turned by yaw.
  void addRectSurface(const std::string& id, double z, const Eigen::Vector2d& center, const Eigen::Vector2d& size,
                      double yaw = 0.0);
  /// Returns the object's index.
  int addObject(const std::string& id, const Vec3& size, const Pose& start, const std::optional<Pose>& goal,
                bool fixed = false);
  void addInspectTask(const std::string& target, const Pose& X_WT, const std::string& requires_removed,
                      const std::string& capability);

  const Scene& scene() const { return scene_; }
  /// Resolves task indices and hands the scene over.
  Scene build();

 private:
  Scene scene_;
};

}  // namespace dash
