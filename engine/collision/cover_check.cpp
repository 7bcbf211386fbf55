// Covers of posed robots over a batch and their pairs (cover_check.h).
#include "engine/collision/cover_check.h"

#include <atomic>
#include <cstdlib>
#include <cstring>

#include "engine/core/check.h"
#include "engine/core/simd_clones.h"

namespace dash {

namespace {

std::atomic<bool>& fastPathFlag() {
  static std::atomic<bool> flag = [] {
    const char* v = std::getenv("DASHBENCH_COVER");
    return !(v != nullptr && (std::strcmp(v, "off") == 0 || std::strcmp(v, "0") == 0));
  }();
  return flag;
}

}  // namespace

bool coverFastPath() { return fastPathFlag().load(std::memory_order_relaxed); }
void setCoverFastPath(bool on) { fastPathFlag().store(on, std::memory_order_relaxed); }

namespace detail {

namespace {

using cover::L;
using cover::SegmentLanes;

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Segment ends in the world, lane by lane: (R, p) * a and * b, (R, p) a batched frame. Computed into
/// locals and copied out: with the outputs possibly aliasing the frames, g++ left the loop scalar.
DASH_SIMD_CLONES void placeSegment(const double (&R)[9][L], const double (&p)[3][L], const Vec3& a_F, const Vec3& b_F,
                                   SegmentLanes& s) {
  const double a0 = a_F[0], a1 = a_F[1], a2 = a_F[2], b0 = b_F[0], b1 = b_F[1], b2 = b_F[2];
  alignas(64) double sa[3][L];
  alignas(64) double sb[3][L];
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < L; ++l) {
      sa[k][l] = p[k][l] + (R[k][l] * a0 + R[3 + k][l] * a1 + R[6 + k][l] * a2);
      sb[k][l] = p[k][l] + (R[k][l] * b0 + R[3 + k][l] * b1 + R[6 + k][l] * b2);
    }
  }
  std::memcpy(s.a, sa, sizeof sa);
  std::memcpy(s.b, sb, sizeof sb);
}

/// Each lane's box (at its radius) and each body's box over every lane, written in place, then the box
/// over the bodies: read back only after all were written (a box read right after the kernel's scalar
/// stores waited on store forwarding: 5 % of sorting 16/64).
void finishBoxes(RobotCoverBatch& out) {
  for (int b = 0; b < out.bodies; ++b)
    cover::setLaneBoxes(out.body[b], out.radius_static[b], out.body_box[b].min().data(), out.body_box[b].max().data());
  if (out.holding) cover::setLaneBoxes(out.held, out.held_static, out.held_box.min().data(), out.held_box.max().data());
  out.whole.setEmpty();
  for (int b = 0; b < out.bodies; ++b) out.whole.extend(out.body_box[b]);
  if (out.holding) out.whole.extend(out.held_box);
}

void setRadii(const CollisionWorld& world, int r, int held_object, RobotCoverBatch& out) {
  const RobotGeometry& rg = world.robot(r);
  DASH_DEMAND_MSG(rg.bodies.size() <= static_cast<std::size_t>(kCoverMaxBodies), "too many robot bodies for the cover");
  out.robot = r;
  out.bodies = static_cast<int>(rg.bodies.size());
  for (int b = 0; b < out.bodies; ++b) {
    out.radius_static[b] = rg.bodies[at(b)].cover.radius_static;
    out.radius_robot[b] = rg.bodies[at(b)].cover.radius_robot;
  }
  out.holding = held_object >= 0;
  if (out.holding) {
    out.held_static = world.object(held_object).held_cover.radius_static;
    out.held_robot = world.object(held_object).held_cover.radius_robot;
  }
}

/// Lane l of `clear` stays 1 only where every lane of the pair is apart; true when none is left.
bool noneLeft(const double* clear) {
  double any = 0.0;
  for (int l = 0; l < L; ++l) any += clear[l];
  return any == 0.0;
}

}  // namespace

void coverFromFrames(const CollisionWorld& world, int r, const FrameBatch& frames, const HeldObject& held,
                     RobotCoverBatch& out) {
  const RobotGeometry& rg = world.robot(r);
  setRadii(world, r, held.object, out);
  for (int b = 0; b < out.bodies; ++b) {
    const int f = bodyBatchFrame(*rg.model, b);
    const CoverCapsule& c = rg.bodies[at(b)].cover;
    placeSegment(frames.R[f], frames.p[f], c.a, c.b, out.body[b]);
  }
  if (out.holding) {
    const CoverCapsule& c = world.object(held.object).held_cover;
    placeSegment(frames.tcp_R, frames.tcp_p, held.X_TO * c.a, held.X_TO * c.b, out.held);
  }
  finishBoxes(out);
}

void coverFromPosed(const CollisionWorld& world, const CollisionContext& context, int r, RobotCoverBatch& out) {
  const RobotGeometry& rg = world.robot(r);
  const auto& posed = context.scratch().robots[at(r)];
  setRadii(world, r, posed.held_object, out);
  alignas(64) double R[9][L];
  alignas(64) double p[3][L];
  for (int b = 0; b < out.bodies; ++b) {
    broadcastBatchPose(posed.frames[at(b)], R, p);
    placeSegment(R, p, rg.bodies[at(b)].cover.a, rg.bodies[at(b)].cover.b, out.body[b]);
  }
  if (out.holding) {
    broadcastBatchPose(posed.X_WO_held, R, p);
    const CoverCapsule& c = world.object(posed.held_object).held_cover;
    placeSegment(R, p, c.a, c.b, out.held);
  }
  finishBoxes(out);
}

void clearRobotPair(const RobotCoverBatch& x, const RobotCoverBatch& y, double* clear) {
  if (!x.whole.intersects(y.whole)) return;
  for (int b1 = 0; b1 < x.bodies; ++b1) {
    if (!x.body_box[b1].intersects(y.whole)) continue;
    for (int b2 = 0; b2 < y.bodies; ++b2) {
      if (!x.body_box[b1].intersects(y.body_box[b2])) continue;
      cover::clearCapsulePair(x.body[b1], x.radius_robot[b1], y.body[b2], y.radius_robot[b2], clear);
    }
    if (y.holding && x.body_box[b1].intersects(y.held_box))
      cover::clearCapsulePair(x.body[b1], x.radius_robot[b1], y.held, y.held_robot, clear);
  }
  if (!x.holding || !x.held_box.intersects(y.whole)) return;
  for (int b2 = 0; b2 < y.bodies; ++b2) {
    if (x.held_box.intersects(y.body_box[b2]))
      cover::clearCapsulePair(x.held, x.held_robot, y.body[b2], y.radius_robot[b2], clear);
  }
  if (y.holding && x.held_box.intersects(y.held_box))
    cover::clearCapsulePair(x.held, x.held_robot, y.held, y.held_robot, clear);
}

void clearAgainstCandidates(const CollisionWorld& world, const CollisionContext& context, const RobotCoverBatch& c,
                            const CandidateView& candidates, std::span<const RobotCoverBatch> others, double* clear) {
  const auto& s = context.scratch();
  auto boxAgainstBodies = [&](const cover::BoxFrame& box, const Aabb& aabb) {
    if (!c.whole.intersects(aabb)) return;
    for (int b = 0; b < c.bodies; ++b)
      if (c.body_box[b].intersects(aabb)) cover::clearCapsuleBox(c.body[b], c.radius_static[b], box, aabb, clear);
  };
  for (const int i : candidates.obstacles) {
    const ObstacleGeometry& o = world.obstacles()[at(i)];
    if (c.whole.intersects(o.aabb)) boxAgainstBodies(cover::boxFrame(o.X_WO, o.half_extents), o.aabb);
  }
  for (const auto& [b1, b2] : candidates.self_pairs) {
    if (c.body_box[b1].intersects(c.body_box[b2]))
      cover::clearCapsulePair(c.body[b1], c.radius_robot[b1], c.body[b2], c.radius_robot[b2], clear);
  }
  if (noneLeft(clear)) return;
  for (const int j : candidates.objects) {
    const Aabb& aabb = s.object_aabb[at(j)];
    if (!c.whole.intersects(aabb)) continue;
    const cover::BoxFrame box = cover::boxFrame(s.object_pose[at(j)], world.object(j).half_extents);
    boxAgainstBodies(box, aabb);
    if (c.holding && c.held_box.intersects(aabb)) cover::clearCapsuleBox(c.held, c.held_static, box, aabb, clear);
  }
  for (const RobotCoverBatch& other : others) clearRobotPair(c, other, clear);
  if (!c.holding || noneLeft(clear)) return;
  for (const int i : candidates.held_obstacles) {
    const ObstacleGeometry& o = world.obstacles()[at(i)];
    if (c.held_box.intersects(o.aabb))
      cover::clearCapsuleBox(c.held, c.held_static, cover::boxFrame(o.X_WO, o.half_extents), o.aabb, clear);
  }
  for (const int b : candidates.held_vs_bodies) {
    if (c.held_box.intersects(c.body_box[b]))
      cover::clearCapsulePair(c.held, c.held_robot, c.body[b], c.radius_robot[b], clear);
  }
}

namespace {

struct WorldCapsule {
  Vec3 a, b;
  double radius;
};

WorldCapsule bodyCapsule(const CollisionWorld& world, const CollisionContext& context, int r, int b, bool vs_static) {
  const CoverCapsule& c = world.robot(r).bodies[at(b)].cover;
  const Pose& X_WF = context.scratch().robots[at(r)].frames[at(b)];
  return {X_WF * c.a, X_WF * c.b, vs_static ? c.radius_static : c.radius_robot};
}

WorldCapsule heldCapsule(const CollisionWorld& world, const CollisionContext& context, int r, bool vs_static) {
  const auto& posed = context.scratch().robots[at(r)];
  const CoverCapsule& c = world.object(posed.held_object).held_cover;
  return {posed.X_WO_held * c.a, posed.X_WO_held * c.b, vs_static ? c.radius_static : c.radius_robot};
}

bool apart(const WorldCapsule& x, const Pose& X_WO, const Vec3& half) {
  return cover::capsuleBoxApart(x.a.data(), x.b.data(), x.radius, cover::boxFrame(X_WO, half));
}

bool apart(const WorldCapsule& x, const WorldCapsule& y) {
  return cover::capsulesApart(x.a.data(), x.b.data(), x.radius, y.a.data(), y.b.data(), y.radius);
}

}  // namespace

bool bodyBoxApart(const CollisionWorld& world, const CollisionContext& context, int r, int b, const Pose& X_WO,
                  const Vec3& half) {
  return coverOn(world) && apart(bodyCapsule(world, context, r, b, true), X_WO, half);
}

bool bodiesApart(const CollisionWorld& world, const CollisionContext& context, int r1, int b1, int r2, int b2) {
  return coverOn(world) &&
         apart(bodyCapsule(world, context, r1, b1, false), bodyCapsule(world, context, r2, b2, false));
}

bool heldBoxApart(const CollisionWorld& world, const CollisionContext& context, int r, const Pose& X_WO,
                  const Vec3& half) {
  return coverOn(world) && apart(heldCapsule(world, context, r, true), X_WO, half);
}

bool heldBodyApart(const CollisionWorld& world, const CollisionContext& context, int holder, int r, int b) {
  return coverOn(world) && apart(heldCapsule(world, context, holder, false), bodyCapsule(world, context, r, b, false));
}

bool heldObjectsApart(const CollisionWorld& world, const CollisionContext& context, int r1, int r2) {
  return coverOn(world) && apart(heldCapsule(world, context, r1, false), heldCapsule(world, context, r2, false));
}

std::uint32_t clearedLanes(const double* clear, int lanes) {
  std::uint32_t bits = 0;
  for (int l = 0; l < lanes; ++l)
    if (clear[l] != 0.0) bits |= 1u << l;
  return bits;
}

}  // namespace detail
}  // namespace dash
