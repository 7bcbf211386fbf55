#pragma once
// Stable resting (formats.md): an object rests when its bottom face lies on a surface's z with its
// footprint inside the surface polygon, or on the top face of another object with its footprint inside
// that face. Both within kSupportTolerance (1 mm); "bottom face" is the box face whose normal points
// most downwards, and all four of its corners must be within the tolerance of the support height, so a
// tilted box does not rest.
#include <array>

#include <Eigen/Core>

#include "engine/scene/object_layout.h"
#include "engine/scene/scene.h"

namespace dash {

inline constexpr double kSupportTolerance = 1e-3;

struct Support {
  enum class Kind { kNone, kSurface, kObject };
  Kind kind = Kind::kNone;
  int index = -1;  ///< surface index (kSurface) or object index (kObject)
  bool found() const { return kind != Kind::kNone; }
};

/// The four corners of the box face whose outward normal is closest to `direction` (world frame).
std::array<Vec3, 4> boxFaceCorners(const BoxShape& box, const Pose& X_WO, const Vec3& direction);

/// True if the convex quadrilateral `footprint` (x, y) lies inside the simple polygon, allowing
/// `tolerance` of overhang.
bool footprintInsidePolygon(const std::array<Eigen::Vector2d, 4>& footprint,
                            const std::vector<Eigen::Vector2d>& polygon, double tolerance);

/// What supports scene object `object` resting at X_WO; other objects are taken from `layout` (only
/// those present, never `object` itself). Surfaces are tried first, then objects, in index order.
Support findSupport(const Scene& scene, int object, const Pose& X_WO, const ObjectLayout& layout);

}  // namespace dash
