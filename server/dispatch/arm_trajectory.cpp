#include "server/dispatch/arm_trajectory.h"

#include <algorithm>
#include <cmath>

#include "engine/core/check.h"

namespace dash::dispatch {

namespace {

constexpr double kSameVelocityTolerance = 1e-9;

/// Index of the segment holding t: points[i].time <= t < points[i+1].time.
std::size_t segmentIndex(const std::vector<TrajectoryWaypoint>& points, double t) {
  auto it = std::upper_bound(points.begin(), points.end(), t,
                             [](double value, const TrajectoryWaypoint& p) { return value < p.time_from_start; });
  const auto after = static_cast<std::size_t>(it - points.begin());
  return after == 0 ? 0 : after - 1;
}

bool allFinite(const JointVector& v) { return v.allFinite(); }

}  // namespace

const char* gripperActionName(GripperCommand::Action action) {
  return action == GripperCommand::Action::kGrasp ? "grasp" : "release";
}

JointVector ArmTrajectory::positionAt(double t) const {
  DASH_DEMAND(!points.empty());
  if (t <= points.front().time_from_start) return points.front().positions;
  if (t >= points.back().time_from_start) return points.back().positions;
  const std::size_t i = segmentIndex(points, t);
  const TrajectoryWaypoint& a = points[i];
  const TrajectoryWaypoint& b = points[i + 1];
  const double T = b.time_from_start - a.time_from_start;
  const double s = (t - a.time_from_start) / T;
  const double s2 = s * s;
  const double s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1;
  const double h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2;
  const double h11 = s3 - s2;
  return h00 * a.positions + h10 * T * a.velocities + h01 * b.positions + h11 * T * b.velocities;
}

JointVector ArmTrajectory::velocityAt(double t) const {
  DASH_DEMAND(!points.empty());
  if (t <= points.front().time_from_start || t >= points.back().time_from_start) {
    return JointVector::Zero(points.front().positions.size());
  }
  const std::size_t i = segmentIndex(points, t);
  const TrajectoryWaypoint& a = points[i];
  const TrajectoryWaypoint& b = points[i + 1];
  const double T = b.time_from_start - a.time_from_start;
  const double s = (t - a.time_from_start) / T;
  const double d00 = 6 * s * s - 6 * s;
  const double d10 = 3 * s * s - 4 * s + 1;
  const double d01 = -6 * s * s + 6 * s;
  const double d11 = 3 * s * s - 2 * s;
  return (d00 * a.positions + d01 * b.positions) / T + d10 * a.velocities + d11 * b.velocities;
}

std::vector<JointVector> velocitiesForPlanPath(const std::vector<JointVector>& q, const std::vector<double>& t) {
  DASH_DEMAND(q.size() == t.size());
  std::vector<JointVector> v;
  v.reserve(q.size());
  for (std::size_t i = 0; i < q.size(); ++i) {
    JointVector vi = JointVector::Zero(q[i].size());
    if (i > 0 && i + 1 < q.size()) {
      const JointVector before = (q[i] - q[i - 1]) / (t[i] - t[i - 1]);
      const JointVector after = (q[i + 1] - q[i]) / (t[i + 1] - t[i]);
      const double scale = 1.0 + std::max(before.cwiseAbs().maxCoeff(), after.cwiseAbs().maxCoeff());
      if ((before - after).cwiseAbs().maxCoeff() <= kSameVelocityTolerance * scale) vi = before;
    }
    v.push_back(vi);
  }
  return v;
}

ArmTrajectory armTrajectoryFromPlan(const Plan& plan, const std::string& robot, double time_scale) {
  DASH_THROW_UNLESS(time_scale > 0.0 && std::isfinite(time_scale), "time_scale must be a positive number");
  const RobotTrajectory* source = plan.findRobot(robot);
  DASH_THROW_UNLESS(source != nullptr, "the plan has no trajectory for robot '" + robot + "'");
  ArmTrajectory out;
  out.robot = robot;
  out.joint_names = source->joint_names;
  std::vector<JointVector> q;
  std::vector<double> t;
  for (const TrajectoryPoint& p : source->points) {
    q.push_back(p.q);
    t.push_back(p.t * time_scale);
  }
  // Velocities need strictly increasing times; leave zeros otherwise (the pre-flight refuses such plans).
  bool increasing = true;
  for (std::size_t i = 1; i < t.size(); ++i) increasing = increasing && t[i] > t[i - 1];
  std::vector<JointVector> v;
  if (increasing) {
    v = velocitiesForPlanPath(q, t);
  } else {
    for (const JointVector& qi : q) v.push_back(JointVector::Zero(qi.size()));
  }
  for (std::size_t i = 0; i < q.size(); ++i) out.points.push_back({q[i], v[i], t[i]});
  for (const PlanEvent& e : plan.events) {
    if (e.robot != robot || e.type == PlanEvent::Type::kInspect) continue;
    const auto action = e.type == PlanEvent::Type::kGrasp ? GripperCommand::Action::kGrasp
                                                          : GripperCommand::Action::kRelease;
    out.gripper.push_back({e.t * time_scale, action, e.object});
  }
  std::stable_sort(out.gripper.begin(), out.gripper.end(),
                   [](const GripperCommand& a, const GripperCommand& b) { return a.t < b.t; });
  return out;
}

PeakSpeed peakSpeed(const ArmTrajectory& trajectory, const JointVector& velocity_max) {
  PeakSpeed peak;
  const auto& pts = trajectory.points;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const double T = pts[i + 1].time_from_start - pts[i].time_from_start;
    if (!(T > 0.0)) continue;
    for (Eigen::Index j = 0; j < pts[i].positions.size(); ++j) {
      // qdot(s) = 6s(1-s) d/T + (1 - 4s + 3s^2) v0 + (3s^2 - 2s) v1 = a s^2 + b s + c
      const double d = (pts[i + 1].positions[j] - pts[i].positions[j]) / T;
      const double v0 = pts[i].velocities[j];
      const double v1 = pts[i + 1].velocities[j];
      const double a = -6 * d + 3 * v0 + 3 * v1;
      const double b = 6 * d - 4 * v0 - 2 * v1;
      const double c = v0;
      double best = std::max(std::abs(c), std::abs(a + b + c));
      if (std::abs(a) > 1e-15) {
        const double s = -b / (2 * a);
        if (s > 0.0 && s < 1.0) best = std::max(best, std::abs(a * s * s + b * s + c));
      }
      const double limit = j < velocity_max.size() ? velocity_max[j] : 0.0;
      const double ratio = limit > 0.0 ? best / limit : (best > 0.0 ? INFINITY : 0.0);
      if (ratio > peak.ratio || (peak.joint < 0 && best > 0.0)) {
        peak = {best, ratio, static_cast<int>(j), static_cast<int>(i)};
      }
    }
  }
  return peak;
}

std::string structuralProblem(const ArmTrajectory& trajectory, int dof) {
  if (static_cast<int>(trajectory.joint_names.size()) != dof) {
    return "expected " + std::to_string(dof) + " joint names, got " + std::to_string(trajectory.joint_names.size());
  }
  if (trajectory.points.empty()) return "the trajectory has no points";
  for (std::size_t i = 0; i < trajectory.points.size(); ++i) {
    const TrajectoryWaypoint& p = trajectory.points[i];
    const std::string where = "point " + std::to_string(i);
    if (p.positions.size() != dof || p.velocities.size() != dof) {
      return where + ": expected " + std::to_string(dof) + " positions and velocities";
    }
    if (!allFinite(p.positions) || !allFinite(p.velocities) || !std::isfinite(p.time_from_start)) {
      return where + ": not a finite number (NaN or infinity)";
    }
    if (i == 0 && std::abs(p.time_from_start) > 1e-9) return "the first point is not at time 0";
    if (i > 0 && !(p.time_from_start > trajectory.points[i - 1].time_from_start)) {
      return where + ": time " + std::to_string(p.time_from_start) + " does not increase";
    }
  }
  for (const GripperCommand& g : trajectory.gripper) {
    if (!std::isfinite(g.t) || g.t < 0.0) {
      return "gripper command at t=" + std::to_string(g.t) + " is not a time from the start";
    }
  }
  return "";
}

}  // namespace dash::dispatch
