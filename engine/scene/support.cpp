#include "engine/scene/support.h"

#include <algorithm>
#include <cmath>

namespace dash {

namespace {

using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double pointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

/// Even-odd rule, with points within `tolerance` of the boundary counted as inside.
bool pointInPolygon(const Vec2& p, const std::vector<Vec2>& polygon, double tolerance) {
  bool inside = false;
  const std::size_t n = polygon.size();
  for (std::size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[j];
    if (pointSegmentDistance(p, a, b) <= tolerance) return true;
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) inside = !inside;
    }
  }
  return inside;
}

/// True if segment a-b passes through the interior of the convex quad shrunk by `tolerance`
/// (Cyrus-Beck clipping against the quad's edges, counter-clockwise order).
bool segmentCrossesQuad(const Vec2& a, const Vec2& b, const std::array<Vec2, 4>& quad, double tolerance) {
  double t0 = 0.0;
  double t1 = 1.0;
  const Vec2 d = b - a;
  for (std::size_t i = 0; i < 4; ++i) {
    const Vec2& e0 = quad[i];
    const Vec2& e1 = quad[(i + 1) % 4];
    const Vec2 edge = e1 - e0;
    const double len = edge.norm();
    if (len <= 0.0) return false;
    // Signed distance to the inside of the edge (CCW: left side is inside), minus the tolerance.
    const double s_a = cross2(edge, a - e0) / len - tolerance;
    const double s_d = cross2(edge, d) / len;
    if (std::abs(s_d) < 1e-15) {
      if (s_a <= 0.0) return false;
      continue;
    }
    const double t = -s_a / s_d;
    if (s_d > 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 >= t1) return false;
  }
  return t1 - t0 > 1e-12;
}

std::array<Vec2, 4> counterClockwise(std::array<Vec2, 4> quad) {
  double twice_area = 0.0;
  for (std::size_t i = 0; i < 4; ++i) twice_area += cross2(quad[i], quad[(i + 1) % 4]);
  if (twice_area < 0.0) std::reverse(quad.begin(), quad.end());
  return quad;
}

std::array<Vec2, 4> footprintOf(const std::array<Vec3, 4>& corners) {
  return counterClockwise({corners[0].head<2>(), corners[1].head<2>(), corners[2].head<2>(), corners[3].head<2>()});
}

bool allAtHeight(const std::array<Vec3, 4>& corners, double z, double tolerance) {
  return std::all_of(corners.begin(), corners.end(), [&](const Vec3& c) { return std::abs(c.z() - z) <= tolerance; });
}

/// Footprint inside a convex quad, with `tolerance` of overhang.
bool footprintInsideQuad(const std::array<Vec2, 4>& footprint, const std::array<Vec2, 4>& quad, double tolerance) {
  for (const Vec2& p : footprint) {
    for (std::size_t i = 0; i < 4; ++i) {
      const Vec2 edge = quad[(i + 1) % 4] - quad[i];
      const double len = edge.norm();
      if (len <= 0.0) return false;
      if (cross2(edge, p - quad[i]) / len < -tolerance) return false;
    }
  }
  return true;
}

}  // namespace

std::array<Vec3, 4> boxFaceCorners(const BoxShape& box, const Pose& X_WO, const Vec3& direction) {
  const Vec3 d_O = X_WO.linear().transpose() * direction;
  int axis = 0;
  d_O.cwiseAbs().maxCoeff(&axis);
  const double sign = d_O[axis] >= 0.0 ? 1.0 : -1.0;
  const Vec3 half = 0.5 * box.size;
  const int u = (axis + 1) % 3;
  const int v = (axis + 2) % 3;
  std::array<Vec3, 4> corners;
  const double su[4] = {-1, 1, 1, -1};
  const double sv[4] = {-1, -1, 1, 1};
  for (int k = 0; k < 4; ++k) {
    Vec3 p_O = Vec3::Zero();
    p_O[axis] = sign * half[axis];
    p_O[u] = su[k] * half[u];
    p_O[v] = sv[k] * half[v];
    corners[static_cast<std::size_t>(k)] = X_WO * p_O;
  }
  return corners;
}

bool footprintInsidePolygon(const std::array<Vec2, 4>& footprint, const std::vector<Vec2>& polygon,
                            double tolerance) {
  if (polygon.size() < 3) return false;
  for (const Vec2& p : footprint) {
    if (!pointInPolygon(p, polygon, tolerance)) return false;
  }
  // Corners inside are not enough for a non-convex polygon: a notch may cut through the footprint.
  const auto quad = counterClockwise(footprint);
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    if (segmentCrossesQuad(polygon[j], polygon[i], quad, tolerance)) return false;
  }
  return true;
}

Support findSupport(const Scene& scene, int object, const Pose& X_WO, const ObjectLayout& layout) {
  const BoxShape& box = scene.objects[static_cast<std::size_t>(object)].shape;
  const auto bottom = boxFaceCorners(box, X_WO, -Vec3::UnitZ());
  const auto footprint = footprintOf(bottom);
  for (std::size_t s = 0; s < scene.surfaces.size(); ++s) {
    const SceneSurface& surface = scene.surfaces[s];
    if (allAtHeight(bottom, surface.z, kSupportTolerance) &&
        footprintInsidePolygon(footprint, surface.polygon, kSupportTolerance)) {
      return {Support::Kind::kSurface, static_cast<int>(s)};
    }
  }
  for (int k = 0; k < layout.size(); ++k) {
    if (k == object || !layout.isPresent(k)) continue;
    const BoxShape& other = scene.objects[static_cast<std::size_t>(k)].shape;
    const auto top = boxFaceCorners(other, layout.X_WO[static_cast<std::size_t>(k)], Vec3::UnitZ());
    const double z = top[0].z();
    if (!allAtHeight(top, z, kSupportTolerance) || !allAtHeight(bottom, z, kSupportTolerance)) continue;
    if (footprintInsideQuad(footprint, footprintOf(top), kSupportTolerance)) {
      return {Support::Kind::kObject, k};
    }
  }
  return {};
}

}  // namespace dash
