#include "engine/collision/grasp_candidates.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace dash {

namespace {

struct FaceAxis {
  GraspCandidate::Face face;
  int axis;     ///< object axis of the face normal
  double sign;  ///< direction of the outward normal along it
};

constexpr FaceAxis kFaces[] = {
    {GraspCandidate::Face::kTop, 2, 1.0},    {GraspCandidate::Face::kBottom, 2, -1.0},
    {GraspCandidate::Face::kPlusX, 0, 1.0},  {GraspCandidate::Face::kMinusX, 0, -1.0},
    {GraspCandidate::Face::kPlusY, 1, 1.0},  {GraspCandidate::Face::kMinusY, 1, -1.0},
};

std::vector<GraspCandidate> urCandidates(const RobotModel& model, const BoxShape& box, const Pose& X_WO) {
  std::vector<GraspCandidate> out;
  const double opening = gripperOpening(model);
  for (const FaceAxis& f : kFaces) {
    const Vec3 normal = f.sign * Vec3::Unit(f.axis);
    const Vec3 z_T = -normal;  // approach into the face
    for (int rotation = 0; rotation < 2; ++rotation) {
      const int closing_axis = (f.axis + 1 + rotation) % 3;  // one of the two in-face axes
      if (box.size[closing_axis] > opening) continue;
      const Vec3 x_T = Vec3::Unit(closing_axis);
      Eigen::Matrix3d R_OT;
      R_OT.col(0) = x_T;
      R_OT.col(1) = z_T.cross(x_T);
      R_OT.col(2) = z_T;
      Pose X_OT = Pose::Identity();
      X_OT.linear() = R_OT;  // TCP at the box centre
      GraspCandidate c;
      c.face = f.face;
      c.rotation = rotation;
      c.X_TO = X_OT.inverse();
      c.X_WT = X_WO * X_OT;
      out.push_back(c);
    }
  }
  return out;
}

std::vector<GraspCandidate> gantryCandidates(const Pose& X_WB, const BoxShape& box, const Pose& X_WO) {
  // The face whose outward normal points most upwards in the world.
  const Vec3 up_O = X_WO.linear().transpose() * X_WB.linear() * Vec3::UnitZ();
  for (const FaceAxis& f : kFaces) {
    const double cos_tilt = f.sign * up_O[f.axis];
    if (cos_tilt < std::cos(kGraspUprightTolerance)) continue;
    const Vec3 p_OT = f.sign * 0.5 * box.size[f.axis] * Vec3::Unit(f.axis);
    Pose X_WT = Pose::Identity();
    // Tool down in the gantry's frame 0: TCP x along frame-0 x, TCP z along frame-0 -z.
    X_WT.linear() = X_WB.linear() * Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal();
    X_WT.translation() = X_WO * p_OT;
    GraspCandidate c;
    c.face = f.face;
    c.X_WT = X_WT;
    c.X_TO = X_WT.inverse() * X_WO;
    return {c};
  }
  return {};
}

}  // namespace

const char* faceName(GraspCandidate::Face face) {
  switch (face) {
    case GraspCandidate::Face::kTop: return "top";
    case GraspCandidate::Face::kBottom: return "bottom";
    case GraspCandidate::Face::kPlusX: return "+x";
    case GraspCandidate::Face::kMinusX: return "-x";
    case GraspCandidate::Face::kPlusY: return "+y";
    case GraspCandidate::Face::kMinusY: return "-y";
  }
  return "?";
}

double gripperOpening(const RobotModel& model) {
  double opening = std::numeric_limits<double>::infinity();
  const Pose X_TF = model.kinematics == KinematicsKind::kUrDh ? model.dh.X_FT.inverse() : Pose::Identity();
  for (const CollisionBody& body : model.bodies) {
    if (!body.is_gripper || body.kind != CollisionBody::Kind::kBox) continue;
    const Vec3 center_T = X_TF * body.box_center;
    const double inner = std::abs(center_T.x()) - body.box_half_extents.x();
    if (inner > 0.0) opening = std::min(opening, 2.0 * inner);
  }
  return opening;
}

std::vector<GraspCandidate> graspCandidates(const RobotModel& model, const Pose& X_WB, const BoxShape& box,
                                            const Pose& X_WO) {
  if (model.kinematics == KinematicsKind::kGantry) return gantryCandidates(X_WB, box, X_WO);
  return urCandidates(model, box, X_WO);
}

}  // namespace dash
