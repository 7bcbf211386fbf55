// Kinematics dispatch, and the Cartesian gantry (gantry3.json): q = [x, y, z], TCP in frame 0 at
// (x, y, beam_height - ram_to_tcp - z) with the tool pointing down (TCP z = -z0, TCP x = x0).
#include <cmath>

#include "engine/core/check.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace detail {
FkResult forwardKinematicsUr(const RobotModel& model, const Pose& X_WB, const JointVector& q);
}  // namespace detail

namespace {

constexpr double kGantryLimitTolerance = 1e-9;

/// Tool-down orientation of the gantry TCP in frame 0: a half turn about x.
Eigen::Matrix3d gantryToolRotation() { return Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal(); }

Vec3 gantryTcpInBase(const RobotModel& model, const JointVector& q) {
  return Vec3(q[0], q[1], model.gantry.beam_height - model.gantry.ram_to_tcp - q[2]);
}

}  // namespace

FkResult forwardKinematics(const RobotModel& model, const Pose& X_WB, const JointVector& q) {
  DASH_DEMAND(q.size() == model.dof());
  if (model.kinematics == KinematicsKind::kUrDh) return detail::forwardKinematicsUr(model, X_WB, q);
  FkResult fk;
  fk.X_WT.linear() = X_WB.linear() * gantryToolRotation();
  fk.X_WT.translation() = X_WB * gantryTcpInBase(model, q);
  fk.X_WF = fk.X_WT;
  return fk;
}

void bodyFrames(const RobotModel& model, const Pose& X_WB, const JointVector& q, std::span<Pose> out) {
  DASH_DEMAND(out.size() == model.bodies.size());
  DASH_DEMAND(q.size() == model.dof());
  if (model.kinematics == KinematicsKind::kUrDh) {
    std::array<Pose, kUrFrames> X_W;
    urFrames(model, X_WB, q, X_W);
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = X_W[static_cast<std::size_t>(model.bodies[i].frame)];
    return;
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    const CollisionBody& b = model.bodies[i];
    const Vec3 c(b.gantry_base_center.x() + (b.moves[0] ? q[0] : 0.0),
                 b.gantry_base_center.y() + (b.moves[1] ? q[1] : 0.0),
                 b.gantry_base_center.z() - (b.moves[2] ? q[2] : 0.0));
    out[i].linear() = X_WB.linear();
    out[i].translation() = X_WB * c;
    out[i].makeAffine();
  }
}

int inverseKinematicsGantry(const RobotModel& model, const Pose& X_WB, const Pose& X_WT, JointVector& q) {
  DASH_DEMAND(model.kinematics == KinematicsKind::kGantry);
  const Eigen::Matrix3d R_BT = X_WB.linear().transpose() * X_WT.linear();
  // Rotation angle from the Frobenius distance: |R1 - R2|_F = 2 sqrt(2) sin(angle / 2), exact near 0.
  const double chord = (R_BT - gantryToolRotation()).norm() / (2.0 * std::sqrt(2.0));
  const double angle = 2.0 * std::asin(std::min(chord, 1.0));
  if (!(angle <= kGantryOrientationTolerance)) return 0;
  const Vec3 p = X_WB.linear().transpose() * (X_WT.translation() - X_WB.translation());
  q.resize(3);
  q << p.x(), p.y(), model.gantry.beam_height - model.gantry.ram_to_tcp - p.z();
  if (!model.withinLimits(q, kGantryLimitTolerance)) return 0;
  q = q.cwiseMax(model.limits.position_min).cwiseMin(model.limits.position_max);
  return 1;
}

std::vector<JointVector> inverseKinematics(const RobotModel& model, const Pose& X_WB, const Pose& X_WT) {
  if (model.kinematics == KinematicsKind::kUrDh) {
    std::array<JointVector, kUrMaxIkSolutions> buffer;
    const int n = inverseKinematicsUr(model, X_WB, X_WT, buffer);
    return {buffer.begin(), buffer.begin() + n};
  }
  JointVector q;
  if (inverseKinematicsGantry(model, X_WB, X_WT, q) == 0) return {};
  return {q};
}

}  // namespace dash
