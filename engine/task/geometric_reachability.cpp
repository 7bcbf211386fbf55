#include "engine/task/geometric_reachability.h"

#include <cmath>

namespace dash {

namespace {
long roundKey(double v) { return std::lround(v * 1e4); }
bool isArm(const SceneRobot& r) { return r.model->kinematics == KinematicsKind::kUrDh; }
}  // namespace

GeometricReachability::GeometricReachability(TransitionSampler& sampler, ReachabilityParams params)
    : sampler_(&sampler), params_(params) {}

bool GeometricReachability::canGrasp(int robot, int object, const Pose& X_WO, GraspClass g) {
  const Vec3 p = X_WO.translation();
  const Quat q(X_WO.linear());
  const auto key = std::make_tuple(robot, object, static_cast<int>(g), roundKey(p.x()), roundKey(p.y()),
                                   roundKey(p.z()), roundKey(q.w() * 10 + q.z()));
  if (auto it = grasp_cache_.find(key); it != grasp_cache_.end()) return it->second;
  ++checks_;
  const bool ok = !sampler_->graspConfigs(robot, object, X_WO, g, 1).empty();
  grasp_cache_.emplace(key, ok);
  return ok;
}

bool GeometricReachability::canHandover(int giver, int receiver, GraspClass, GraspClass) const {
  const Scene& scene = sampler_->world().scene();
  const SceneRobot& a = scene.robots[giver];
  const SceneRobot& b = scene.robots[receiver];
  if (!isArm(a) || !isArm(b)) return false;
  return (a.X_WB.translation() - b.X_WB.translation()).norm() <= params_.max_handover_base_distance;
}

bool GeometricReachability::canInspect(int robot, int task) {
  const Scene& scene = sampler_->world().scene();
  const Pose& X_WT = scene.tasks[task].X_WT;
  for (const JointVector& q : sampler_->ikSolutions(robot, X_WT))
    if (sampler_->staticFree({robot, q, HeldObject{}})) return true;
  return false;
}

TaskReachability GeometricReachability::oracle() {
  const Scene& scene = sampler_->world().scene();
  TaskReachability reach;
  reach.canGrasp = [this](int r, int o, const Pose& X, GraspClass g) { return canGrasp(r, o, X, g); };
  reach.canHandover = [this](int a, int b, int, GraspClass g1, GraspClass g2) { return canHandover(a, b, g1, g2); };
  reach.canInspect = [this](int r, int k) { return canInspect(r, k); };
  reach.graspCost = [&scene](int r, const Pose& X) {
    Vec3 d = X.translation() - scene.robots[r].X_WB.translation();
    d.z() = 0.0;
    return d.norm();
  };
  reach.handoverCost = [&scene](int a, int b) {
    return (scene.robots[a].X_WB.translation() - scene.robots[b].X_WB.translation()).norm();
  };
  return reach;
}

}  // namespace dash
