#pragma once
// Poses in scene, plan and robot files: {"p": [x, y, z], "q": [qx, qy, qz, qw]} with a unit quaternion.
#include <cmath>
#include <string>

#include "engine/core/json_reader.h"
#include "engine/geometry/pose.h"

namespace dash {

/// How far from 1 a file quaternion's norm may be.
inline constexpr double kUnitQuaternionTolerance = 1e-6;

/// The pose at `path`; errors name "path.p", "path.q" or "path.q[i]".
template <class JsonT>
Pose readPose(const JsonReader<JsonT>& reader, const JsonT& value, const std::string& path) {
  const auto p = reader.numbersAt(value, path, "p", 3);
  const std::string q_path = reader.join(path, "q");
  const auto q = reader.numbersAt(value, path, "q", 4);
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (std::abs(norm - 1.0) > kUnitQuaternionTolerance) reader.fail(q_path, "quaternion is not unit length");
  return makePose(Vec3(p[0], p[1], p[2]), quatFromXYZW({q[0], q[1], q[2], q[3]}));
}

}  // namespace dash
