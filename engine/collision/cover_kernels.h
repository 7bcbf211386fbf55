#pragma once
// Separation tests of the covers (link_cover.h), one pair at a time (inline, branch-free, so that a
// loop over the lanes of a batch vectorises) and over kBatchLanes lanes. Each test is conservative:
// it says "apart" only when the two shapes are separated (by a separating axis, or by a distance
// between segments larger than the sum of the radii). Rounding: the coordinates are below 100 m and
// the segments below 2 m, so each computed projection or distance is off by less than 1e-12 m; near
// parallel segments (sin of the angle below 1e-6) take the parallel branch, off by less than 1e-6 m
// of their length. kCoverMargin (1e-4 m) covers both.
#include <algorithm>
#include <cmath>

#include "engine/geometry/pose.h"
#include "engine/robots/batch_kinematics.h"

namespace dash::cover {

inline constexpr int L = kBatchLanes;
inline constexpr double kTiny = 1e-300;

/// A box in the world: axes (columns of R, R[3 * k + row]), centre c, half extents h.
struct BoxFrame {
  double R[9];
  double c[3];
  double h[3];
};
BoxFrame boxFrame(const Pose& X_WO, const Vec3& half);

/// Value selects only (std::clamp, std::min and std::max return references, which g++ does not
/// vectorise below AVX-512).
inline double clampd(double v, double lo, double hi) {
  const double x = v < lo ? lo : v;
  return x > hi ? hi : x;
}
inline double mind(double a, double b) { return a < b ? a : b; }
inline double maxd(double a, double b) { return a > b ? a : b; }

inline double dot3(const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

/// The capsule a-b (world), radius r, against the box: apart along one of the box's axes, or along the
/// axis from the box's nearest point to the segment's point nearest the box centre.
inline bool capsuleBoxApart(const double* a_W, const double* b_W, double r, const BoxFrame& box) {
  double a[3], b[3], d[3];
  const double da[3] = {a_W[0] - box.c[0], a_W[1] - box.c[1], a_W[2] - box.c[2]};
  const double db[3] = {b_W[0] - box.c[0], b_W[1] - box.c[1], b_W[2] - box.c[2]};
  bool apart = false;
  for (int k = 0; k < 3; ++k) {
    a[k] = dot3(&box.R[3 * k], da);
    b[k] = dot3(&box.R[3 * k], db);
    d[k] = b[k] - a[k];
    apart |= (mind(a[k], b[k]) - r > box.h[k]) | (maxd(a[k], b[k]) + r < -box.h[k]);
  }
  const double t = clampd(-dot3(a, d) / maxd(dot3(d, d), kTiny), 0.0, 1.0);
  double n[3];
  double hb = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double p = a[k] + t * d[k];
    n[k] = p - clampd(p, -box.h[k], box.h[k]);
    hb += box.h[k] * std::abs(n[k]);
  }
  // Along n the box spans [-hb, hb] and the capsule [min(a.n, b.n) - r |n|, ...] (n unnormalised;
  // squared to keep sqrt, which sets errno and stops vectorisation, out).
  const double gap = mind(dot3(a, n), dot3(b, n)) - hb;
  apart |= (gap > 0.0) & (gap * gap > r * r * dot3(n, n));
  return apart;
}

/// Squared distance between the segments a1-b1 and a2-b2 (closest points as in Ericson, Real-Time
/// Collision Detection 5.1.9, branch-free).
inline double segmentDistanceSquared(const double* a1, const double* b1, const double* a2, const double* b2) {
  const double d1[3] = {b1[0] - a1[0], b1[1] - a1[1], b1[2] - a1[2]};
  const double d2[3] = {b2[0] - a2[0], b2[1] - a2[1], b2[2] - a2[2]};
  const double r[3] = {a1[0] - a2[0], a1[1] - a2[1], a1[2] - a2[2]};
  const double A = dot3(d1, d1), E = dot3(d2, d2), F = dot3(d2, r), C = dot3(d1, r), B = dot3(d1, d2);
  const double denom = A * E - B * B;
  // Every quotient is computed, then selected (a division inside a branch stops vectorisation).
  const double s_lines = clampd((B * F - C * E) / maxd(denom, kTiny), 0.0, 1.0);
  const double s0 = denom > 1e-12 * A * E ? s_lines : 0.0;
  const double t0 = (B * s0 + F) / maxd(E, kTiny);
  const double t = clampd(t0, 0.0, 1.0);
  const double s_low = clampd(-C / maxd(A, kTiny), 0.0, 1.0);
  const double s_high = clampd((B - C) / maxd(A, kTiny), 0.0, 1.0);
  const double s = t0 < 0.0 ? s_low : (t0 > 1.0 ? s_high : s0);
  double dd = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double e = (a1[k] + s * d1[k]) - (a2[k] + t * d2[k]);
    dd += e * e;
  }
  return dd;
}

inline bool capsulesApart(const double* a1, const double* b1, double r1, const double* a2, const double* b2,
                          double r2) {
  return segmentDistanceSquared(a1, b1, a2, b2) > (r1 + r2) * (r1 + r2);
}

/// Lanes of a batch: segment end points per lane, a[k][lane], and each lane's box (setLaneBoxes).
struct SegmentLanes {
  alignas(64) double a[3][L];
  alignas(64) double b[3][L];
  alignas(64) double lo[3][L];
  alignas(64) double hi[3][L];
};

/// s.lo, s.hi: the box of each lane's capsule at radius r (the largest radius the lanes are tested at);
/// `lo`, `hi` (3 values each): the box over every lane.
void setLaneBoxes(SegmentLanes& s, double r, double* lo, double* hi);

/// clear[l] = 0 where the capsule of lane l (radius r) may meet the box (whose world box is `aabb`):
/// apart when the lane's box misses `aabb` or by capsuleBoxApart. False when no lane's box meets it
/// (nothing to do), else true.
bool clearCapsuleBox(const SegmentLanes& s, double r, const BoxFrame& box, const Eigen::AlignedBox3d& aabb,
                     double* clear);
/// clear[l] = 0 where the capsules of lane l may meet (apart when their lane boxes miss each other,
/// or by capsulesApart).
void clearCapsulePair(const SegmentLanes& s1, double r1, const SegmentLanes& s2, double r2, double* clear);

}  // namespace dash::cover
