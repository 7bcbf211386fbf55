#include "engine/collision/collision_world.h"

#include <algorithm>
#include <cmath>
#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/sphere.h>

#include "engine/core/check.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

/// An object's contact box keeps at least this fraction of each edge, however small the object.
constexpr double kMinContactFraction = 0.5;
/// Far more than any planner needs; a larger one is a typo (mm for m).
constexpr double kMaxClearance = 0.1;

/// A body's FCL shape grown by `margin` (the same shape when margin is 0).
ShapePtr grownBody(const BodyGeometry& g, const ShapePtr& exact, double margin) {
  if (margin <= 0.0) return exact;
  if (!g.is_capsule) return std::make_shared<const fcl::Boxd>(2.0 * (g.half_extents + Vec3::Constant(margin)));
  const double length = (g.b - g.a).norm();
  if (length > 0.0) return std::make_shared<const fcl::Capsuled>(g.radius + margin, length);
  return std::make_shared<const fcl::Sphered>(g.radius + margin);
}

BodyGeometry makeBodyGeometry(const CollisionBody& body, double clearance) {
  BodyGeometry g;
  g.is_gripper = body.is_gripper;
  if (body.kind == CollisionBody::Kind::kCapsule) {
    g.is_capsule = true;
    g.a = body.capsule.a;
    g.b = body.capsule.b;
    g.radius = body.capsule.radius;
    const Vec3 axis = g.b - g.a;
    const double length = axis.norm();
    g.X_FG = makePose(0.5 * (g.a + g.b), length > 0.0 ? Quat::FromTwoVectors(Vec3::UnitZ(), axis) : Quat::Identity());
    if (length > 0.0) {
      g.shape = std::make_shared<const fcl::Capsuled>(g.radius, length);
    } else {
      g.shape = std::make_shared<const fcl::Sphered>(g.radius);
    }
    g.extent = std::max(g.a.norm(), g.b.norm()) + g.radius;
  } else {
    g.is_capsule = false;
    // The shape sits at box_center in F (zero for a gantry, whose body frame is the moved centre).
    g.center = body.box_center;
    g.half_extents = body.box_half_extents;
    g.X_FG = makePose(g.center);
    g.shape = std::make_shared<const fcl::Boxd>(2.0 * g.half_extents);
    g.extent = g.center.norm() + g.half_extents.norm();
  }
  g.cover = g.is_capsule ? capsuleCover(g.a, g.b, g.radius, clearance) : boxCover(g.center, g.half_extents, clearance);
  g.shape_vs_static = grownBody(g, g.shape, clearance);
  g.shape_vs_robot = grownBody(g, g.shape, 0.5 * clearance);
  return g;
}

/// Levers and reach of a UR arm. Joint i (1-based) turns frame i and everything after it about the z
/// axis of frame i-1. Frame i's origin is |a_i| from that axis; each later link adds at most
/// sqrt(a_k^2 + d_k^2); a body point adds at most its distance from its own frame's origin.
void urBounds(const RobotModel& model, RobotGeometry& rg, const std::vector<int>& frames) {
  const auto& dh = model.dh;
  constexpr int kJoints = 6;
  auto link = [&](int k) { return std::hypot(dh.a[static_cast<std::size_t>(k - 1)], dh.d[static_cast<std::size_t>(k - 1)]); };
  auto lever = [&](int joint, int frame, double local) {
    if (frame < joint) return 0.0;
    double r = std::abs(dh.a[static_cast<std::size_t>(joint - 1)]);
    for (int k = joint + 1; k <= frame; ++k) r += link(k);
    return r + local;
  };
  double reach = 0.0;
  for (std::size_t b = 0; b < rg.bodies.size(); ++b) {
    JointVector levers(kJoints);
    for (int i = 1; i <= kJoints; ++i) levers[i - 1] = lever(i, frames[b], rg.bodies[b].extent);
    rg.body_lever.push_back(levers);
    double from_base = rg.bodies[b].extent;
    for (int k = 1; k <= frames[b]; ++k) from_base += link(k);
    reach = std::max(reach, from_base);
  }
  rg.tcp_lever.resize(kJoints);
  for (int i = 1; i <= kJoints; ++i) rg.tcp_lever[i - 1] = lever(i, kJoints, dh.X_FT.translation().norm());
  const Vec3 origin = rg.robot->X_WB.translation();
  rg.reach = Aabb(origin - Vec3::Constant(reach), origin + Vec3::Constant(reach));
}

/// Levers and reach of a gantry: every body is a box translated by the axes it follows.
void gantryBounds(const RobotModel& model, RobotGeometry& rg) {
  const int dof = model.dof();
  Aabb reach_B;  // in frame 0
  for (std::size_t b = 0; b < rg.bodies.size(); ++b) {
    const CollisionBody& body = model.bodies[b];
    JointVector levers = JointVector::Zero(dof);
    Vec3 lo = body.gantry_base_center;
    Vec3 hi = body.gantry_base_center;
    for (int i = 0; i < dof && i < 3; ++i) {
      if (!body.moves[static_cast<std::size_t>(i)]) continue;
      levers[i] = 1.0;
      // x and y move the box along +x, +y; z moves it down (gantry3.json).
      const double sign = i == 2 ? -1.0 : 1.0;
      const double a = sign * model.limits.position_min[i];
      const double c = sign * model.limits.position_max[i];
      lo[i] += std::min(a, c);
      hi[i] += std::max(a, c);
    }
    rg.body_lever.push_back(levers);
    reach_B.extend(lo - body.box_half_extents);
    reach_B.extend(hi + body.box_half_extents);
  }
  rg.tcp_lever = JointVector::Ones(dof);
  rg.reach.setEmpty();
  for (int k = 0; k < 8; ++k) {
    rg.reach.extend(rg.robot->X_WB * reach_B.corner(static_cast<Aabb::CornerType>(k)));
  }
}

/// The TCP in each gripper body's frame, from two configurations (it must not depend on q).
void setGripperTcp(const RobotModel& model, RobotGeometry& rg) {
  const JointVector lo = model.limits.position_min;
  const JointVector hi = model.limits.position_max;
  const JointVector q1 = 0.5 * (lo + hi);
  const JointVector q2 = lo + 0.3 * (hi - lo);
  std::vector<Pose> f1(rg.bodies.size()), f2(rg.bodies.size());
  bodyFrames(model, rg.robot->X_WB, q1, f1);
  bodyFrames(model, rg.robot->X_WB, q2, f2);
  const Pose X_WT1 = forwardKinematics(model, rg.robot->X_WB, q1).X_WT;
  const Pose X_WT2 = forwardKinematics(model, rg.robot->X_WB, q2).X_WT;
  for (std::size_t b = 0; b < rg.bodies.size(); ++b) {
    BodyGeometry& g = rg.bodies[b];
    if (!g.is_gripper) continue;
    g.X_FT = f1[b].inverse() * X_WT1;
    DASH_DEMAND_MSG((f2[b] * g.X_FT).isApprox(X_WT2, 1e-9), "a gripper body does not move with the tool");
  }
}

}  // namespace

Aabb boxAabb(const Pose& X, const Vec3& half) {
  const Vec3 extent = X.linear().cwiseAbs() * half;
  return Aabb(X.translation() - extent, X.translation() + extent);
}

PosedShape heldStaticShape(const CollisionWorld& world, int object, const Pose& X_WO) {
  const ObjectGeometry& g = world.object(object);
  // The axis that points most nearly up or down; its face with the lower outward normal is the bottom.
  int k = 0;
  X_WO.linear().row(2).cwiseAbs().maxCoeff(&k);
  const double down = X_WO.linear()(2, k) > 0.0 ? -1.0 : 1.0;  // object-frame sign of the lowest face
  // The shape spans [down * (h - tol), -down * (h + clearance)] along k: its centre is offset by
  // -down * (tol + clearance) / 2.
  Vec3 offset = Vec3::Zero();
  offset[k] = -down * 0.5 * (g.bottom_tolerance + world.clearance());
  return {g.held_vs_static[static_cast<std::size_t>(k)].get(), X_WO * makePose(offset)};
}

ObjectGeometry makeObjectGeometry(const Vec3& size, double clearance) {
  ObjectGeometry g;
  g.shape = std::make_shared<const fcl::Boxd>(size);
  g.half_extents = 0.5 * size;
  Vec3 contact = size;
  for (int k = 0; k < 3; ++k) contact[k] = std::max(size[k] - 2.0 * kObjectContactTolerance, kMinContactFraction * size[k]);
  g.contact_shape = std::make_shared<const fcl::Boxd>(contact);
  g.contact_half_extents = 0.5 * contact;
  g.bottom_tolerance = std::min(kHeldBottomTolerance, 0.5 * (1.0 - kMinContactFraction) * size.minCoeff());
  for (int k = 0; k < 3; ++k) {
    Vec3 held = size + Vec3::Constant(2.0 * clearance);
    held[k] = size[k] + clearance - g.bottom_tolerance;
    g.held_vs_static[static_cast<std::size_t>(k)] = std::make_shared<const fcl::Boxd>(held);
  }
  g.held_in_transit = clearance > 0.0 ? std::make_shared<const fcl::Boxd>(size + Vec3::Constant(2.0 * clearance)) : g.shape;
  g.held_vs_robot = clearance > 0.0 ? std::make_shared<const fcl::Boxd>(size + Vec3::Constant(clearance)) : g.shape;
  g.held_cover = boxCover(Vec3::Zero(), g.half_extents, clearance);
  return g;
}

CollisionWorld::CollisionWorld(const Scene& scene, CollisionWorldOptions options) : scene_(&scene), options_(options) {
  DASH_THROW_UNLESS(std::isfinite(options.clearance) && options.clearance >= 0.0 && options.clearance <= kMaxClearance,
                    "clearance must be between 0 and 0.1 m");
  for (const SceneObstacle& o : scene.obstacles) {
    ObstacleGeometry g;
    g.shape = std::make_shared<const fcl::Boxd>(o.shape.size);
    g.X_WO = o.X_WO;
    g.half_extents = 0.5 * o.shape.size;
    g.aabb = boxAabb(o.X_WO, 0.5 * o.shape.size);
    obstacles_.push_back(std::move(g));
    all_obstacles_.push_back(static_cast<int>(all_obstacles_.size()));
  }
  for (const SceneObject& o : scene.objects) objects_.push_back(makeObjectGeometry(o.shape.size, options.clearance));
  for (const SceneRobot& r : scene.robots) {
    DASH_DEMAND(r.model != nullptr);
    const RobotModel& model = *r.model;
    RobotGeometry rg;
    rg.robot = &r;
    rg.model = &model;
    std::vector<int> frames;
    for (const CollisionBody& body : model.bodies) {
      if (!body.is_gripper) rg.non_gripper_bodies.push_back(static_cast<int>(rg.bodies.size()));
      rg.bodies.push_back(makeBodyGeometry(body, options.clearance));
      frames.push_back(body.frame);
    }
    setGripperTcp(model, rg);
    if (model.kinematics == KinematicsKind::kUrDh) {
      urBounds(model, rg, frames);
    } else {
      gantryBounds(model, rg);
    }
    for (std::size_t i = 0; i < obstacles_.size(); ++i) {
      if (rg.reach.intersects(obstacles_[i].aabb)) rg.nearby_obstacles.push_back(static_cast<int>(i));
    }
    robots_.push_back(std::move(rg));
  }
}

}  // namespace dash
