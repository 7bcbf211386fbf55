#pragma once
// Rigid poses. Names follow Drake's monogram notation: X_WB is the pose of frame B in frame W,
// p_WQ the position of point Q in W.
#include <Eigen/Geometry>
#include <array>

namespace dash {

using Pose = Eigen::Isometry3d;
using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

inline Pose makePose(const Vec3& p, const Quat& q) {
  Pose X = Pose::Identity();
  X.linear() = q.normalized().toRotationMatrix();
  X.translation() = p;
  return X;
}

inline Pose makePose(const Vec3& p) {
  Pose X = Pose::Identity();
  X.translation() = p;
  return X;
}

/// Quaternion as stored in files: [qx, qy, qz, qw].
inline std::array<double, 4> quatXYZW(const Pose& X) {
  const Quat q(X.linear());
  return {q.x(), q.y(), q.z(), q.w()};
}

inline Quat quatFromXYZW(const std::array<double, 4>& q) { return Quat(q[3], q[0], q[1], q[2]); }

/// Angle of the rotation between two poses, in [0, pi].
inline double rotationDistance(const Pose& A, const Pose& B) {
  return Eigen::AngleAxisd(A.linear().transpose() * B.linear()).angle();
}

inline double translationDistance(const Pose& A, const Pose& B) {
  return (A.translation() - B.translation()).norm();
}

}  // namespace dash
