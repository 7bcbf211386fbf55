#pragma once
// Conservative covers of the collision geometry (issue 38): one capsule per robot body and per held
// object that CONTAINS the exact shape grown by the clearance, plus kCoverMargin. When two covers (or
// a cover and an exact box) are separated, so are the exact shapes, and the exact check (FCL, in
// collision_queries.cpp) would find no collision there: the cover may clear such a pair without it.
// What the cover cannot clear goes to the exact check, which decides; the validator and the
// certificate use the exact geometry only.
//
// Containment, by construction:
//  - a capsule body (segment a-b, radius r) grown by g is the capsule a-b of radius r + g; its cover
//    is that capsule with radius r + g + kCoverMargin;
//  - a box (centre c, half extents h) grown by g: the cover's segment runs along the box's longest
//    axis k through c, over c +- (h_k + G) e_k (G >= g, the largest growth used), radius
//    sqrt((h_i + g)^2 + (h_j + g)^2) + kCoverMargin over the other two axes. A point x of the grown
//    box has |x_k - c_k| <= h_k + g, so the segment point c + (x_k - c_k) e_k exists and lies
//    sqrt((x_i - c_i)^2 + (x_j - c_j)^2) <= that radius from x.
// tests/collision/link_cover_test.cpp checks both (every corner of every grown box lies inside: the
// capsule is convex, so the box, the hull of its corners, does).
//
// kCoverMargin (0.1 mm) absorbs the rounding of the separation tests and of the batched kinematics
// (both below 1e-9 m; see cover_kernels.h) and FCL's own tolerance (GJK/EPA to about 1e-6 m), so
// that a pair the cover clears is one FCL finds apart.
#include "engine/geometry/pose.h"

namespace dash {

inline constexpr double kCoverMargin = 1e-4;  ///< metres

/// A capsule in a shape's frame: segment a-b, one radius per growth.
struct CoverCapsule {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  double radius_static = 0.0;  ///< contains the shape grown by the whole clearance (vs static geometry)
  double radius_robot = 0.0;   ///< contains the shape grown by half the clearance (vs robot parts)
};

/// Cover of the capsule a-b of radius r (clearance: the world's; the growths are it and half of it).
CoverCapsule capsuleCover(const Vec3& a, const Vec3& b, double radius, double clearance);

/// Cover of the box of half extents `half` centred at `center` (axis-aligned in its frame).
CoverCapsule boxCover(const Vec3& center, const Vec3& half, double clearance);

}  // namespace dash
