#include "engine/robots/cartesian_path.h"

#include <algorithm>
#include <cmath>

#include "engine/robots/kinematics.h"

namespace dash {

namespace {

/// Halvings of one segment at most (2^24 pieces: far beyond any max_points).
constexpr int kMaxDepth = 24;

struct Line {
  const RobotModel& model;
  const Pose& X_WB;
  Vec3 p0, p1;
  Quat r0, r1;
  const CartesianPathOptions& options;

  Pose at(double s) const {
    Pose X = Pose::Identity();
    X.linear() = r0.slerp(s, r1).toRotationMatrix();
    X.translation() = p0 + s * (p1 - p0);
    return X;
  }
  /// How far a point within the reach of the TCP at X is from where the line puts it at s (bound).
  double deviation(const Pose& X, double s) const {
    const Pose target = at(s);
    const double angle = Eigen::AngleAxisd(target.linear().transpose() * X.linear()).angle();
    return (X.translation() - target.translation()).norm() + options.reach * std::abs(angle);
  }
};

/// The IK solution of X_WT nearest to `near` (revolute joints of a UR arm moved by 2 pi towards it
/// where the limits allow), or nullopt.
std::optional<JointVector> nearestSolution(const RobotModel& model, const Pose& X_WB, const Pose& X_WT,
                                           const JointVector& near) {
  std::optional<JointVector> best;
  double best_distance = 0.0;
  for (JointVector q : inverseKinematics(model, X_WB, X_WT)) {
    if (model.kinematics == KinematicsKind::kUrDh)
      for (int i = 0; i < q.size(); ++i) {
        const double shifted = near[i] + wrapToPi(q[i] - near[i]);
        if (shifted >= model.limits.position_min[i] && shifted <= model.limits.position_max[i]) q[i] = shifted;
      }
    const double d = (q - near).cwiseAbs().maxCoeff();
    if (!best || d < best_distance) {
      best = q;
      best_distance = d;
    }
  }
  return best;
}

/// Appends the waypoints after q0 up to q1 (fractions s0, s1 of the line); false when the line leaves
/// the branch or needs too many waypoints.
bool refine(const Line& line, double s0, const JointVector& q0, double s1, const JointVector& q1, int depth,
            std::vector<JointVector>& out) {
  const JointVector q_mid = 0.5 * (q0 + q1);
  const double s = 0.5 * (s0 + s1);
  // Measured at the quarters too: a segment whose sag changes sign inside it strays least at its middle.
  double deviation = 0.0;
  for (const double u : {0.25, 0.5, 0.75}) {
    const Pose X = forwardKinematics(line.model, line.X_WB, q0 + u * (q1 - q0)).X_WT;
    deviation = std::max(deviation, line.deviation(X, s0 + u * (s1 - s0)));
  }
  if (deviation <= line.options.deviation + line.options.growth * s0 * (line.p1 - line.p0).norm()) {
    out.push_back(q1);
    return true;
  }
  if (depth >= kMaxDepth || static_cast<int>(out.size()) >= line.options.max_points) return false;
  const std::optional<JointVector> q = nearestSolution(line.model, line.X_WB, line.at(s), q_mid);
  // On the branch that joins the ends the waypoint lies near the middle of the segment (it differs by
  // the sag, a fraction of the segment); another branch (a wrist flip) lies far from it.
  if (!q || (*q - q_mid).cwiseAbs().maxCoeff() > 0.5 * (q1 - q0).cwiseAbs().maxCoeff() + 1e-9) return false;
  return refine(line, s0, q0, s, *q, depth + 1, out) && refine(line, s, *q, s1, q1, depth + 1, out);
}

}  // namespace

std::optional<std::vector<JointVector>> cartesianPath(const RobotModel& model, const Pose& X_WB,
                                                      const JointVector& q_from, const JointVector& q_to,
                                                      const CartesianPathOptions& options) {
  const Pose X0 = forwardKinematics(model, X_WB, q_from).X_WT;
  const Pose X1 = forwardKinematics(model, X_WB, q_to).X_WT;
  const Line line{model, X_WB, X0.translation(), X1.translation(), Quat(X0.linear()), Quat(X1.linear()), options};
  std::vector<JointVector> path{q_from};
  if ((q_to - q_from).cwiseAbs().maxCoeff() <= 0.0) return path;
  if (!refine(line, 0.0, q_from, 1.0, q_to, 0, path)) return std::nullopt;
  return path;
}

std::optional<std::vector<JointVector>> backOffLine(const RobotModel& model, const Pose& X_WB, const JointVector& q,
                                                    const JointVector& q_end) {
  return cartesianPath(model, X_WB, q, q_end, CartesianPathOptions{.growth = kBackOffGrowth});
}

std::vector<JointVector> backOffPath(const RobotModel& model, const Pose& X_WB, const JointVector& q,
                                     const JointVector& q_end) {
  return backOffLine(model, X_WB, q, q_end).value_or(std::vector<JointVector>{q, q_end});
}

bool backsOffSideways(const Pose& X_WT, const std::optional<Vec3>& direction_W) {
  const Vec3 axis_W = direction_W ? direction_W->normalized() : Vec3(X_WT.linear().col(2));
  return std::abs(axis_W.z()) < 0.7;
}

Pose backOffPose(const Pose& X_WT, double distance, double lift, const std::optional<Vec3>& direction_W) {
  Pose X_WTpre =
      direction_W ? makePose(distance * direction_W->normalized()) * X_WT : X_WT * makePose(Vec3(0, 0, -distance));
  if (backsOffSideways(X_WT, direction_W)) X_WTpre = makePose(Vec3(0, 0, lift)) * X_WTpre;
  return X_WTpre;
}

double pathLength(const std::vector<JointVector>& path) {
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += (path[i] - path[i - 1]).norm();
  return length;
}

}  // namespace dash
