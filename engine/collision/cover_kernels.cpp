// Lane loops of the cover tests (cover_kernels.h), cloned for AVX-512, AVX2 and SSE2.
#include "engine/collision/cover_kernels.h"

#include <cstring>

#include "engine/core/simd_clones.h"

namespace dash::cover {

BoxFrame boxFrame(const Pose& X_WO, const Vec3& half) {
  BoxFrame box;
  for (int col = 0; col < 3; ++col) {
    for (int row = 0; row < 3; ++row) box.R[3 * col + row] = X_WO.linear()(row, col);
    box.c[col] = X_WO.translation()[col];
    box.h[col] = half[col];
  }
  return box;
}

DASH_SIMD_CLONES void setLaneBoxes(SegmentLanes& s, double r, double* lo, double* hi) {
  static_assert((L & (L - 1)) == 0, "the reduction below halves the lanes");
  // Into locals first: with `lo` and `hi` possibly aliasing `s`, g++ checked at run time and kept
  // to 128-bit vectors.
  alignas(64) double x[3][L];
  alignas(64) double y[3][L];
  for (int k = 0; k < 3; ++k) {
    for (int l = 0; l < L; ++l) {
      x[k][l] = mind(s.a[k][l], s.b[k][l]) - r;
      y[k][l] = maxd(s.a[k][l], s.b[k][l]) + r;
    }
  }
  std::memcpy(s.lo, x, sizeof x);
  std::memcpy(s.hi, y, sizeof y);
  // Halving over the lanes, a tree rather than a chain of eight (a min over doubles that may be NaN is
  // no reduction g++ vectorises by itself).
  for (int half = L / 2; half >= 1; half /= 2) {
    for (int k = 0; k < 3; ++k) {
      for (int l = 0; l < half; ++l) {
        x[k][l] = mind(x[k][l], x[k][l + half]);
        y[k][l] = maxd(y[k][l], y[k][l + half]);
      }
    }
  }
  for (int k = 0; k < 3; ++k) {
    lo[k] = x[k][0];
    hi[k] = y[k][0];
  }
}

DASH_SIMD_CLONES bool clearCapsuleBox(const SegmentLanes& s, double r, const BoxFrame& box,
                                      const Eigen::AlignedBox3d& aabb, double* clear) {
  alignas(64) double meets[L];
  double any = 0.0;
  for (int l = 0; l < L; ++l) {
    bool m = true;
    for (int k = 0; k < 3; ++k) m &= (s.lo[k][l] <= aabb.max()[k]) & (s.hi[k][l] >= aabb.min()[k]);
    meets[l] = m ? 1.0 : 0.0;
    any += meets[l];
  }
  if (any == 0.0) return false;
  for (int l = 0; l < L; ++l) {
    const double a[3] = {s.a[0][l], s.a[1][l], s.a[2][l]};
    const double b[3] = {s.b[0][l], s.b[1][l], s.b[2][l]};
    clear[l] *= (meets[l] == 0.0) | capsuleBoxApart(a, b, r, box) ? 1.0 : 0.0;
  }
  return true;
}

DASH_SIMD_CLONES void clearCapsulePair(const SegmentLanes& s1, double r1, const SegmentLanes& s2, double r2,
                                       double* clear) {
  double any = 0.0;
  for (int l = 0; l < L; ++l) {
    bool m = true;
    for (int k = 0; k < 3; ++k) m &= (s1.lo[k][l] <= s2.hi[k][l]) & (s1.hi[k][l] >= s2.lo[k][l]);
    any += m ? 1.0 : 0.0;
  }
  if (any == 0.0) return;
  for (int l = 0; l < L; ++l) {
    const double a1[3] = {s1.a[0][l], s1.a[1][l], s1.a[2][l]};
    const double b1[3] = {s1.b[0][l], s1.b[1][l], s1.b[2][l]};
    const double a2[3] = {s2.a[0][l], s2.a[1][l], s2.a[2][l]};
    const double b2[3] = {s2.b[0][l], s2.b[1][l], s2.b[2][l]};
    clear[l] *= capsulesApart(a1, b1, r1, a2, b2, r2) ? 1.0 : 0.0;
  }
}

}  // namespace dash::cover
