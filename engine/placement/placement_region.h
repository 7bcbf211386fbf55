#pragma once
// Where an object may be put down: a scene surface polygon (CGAL Polygon_2) at a height. Used to
// resample object poses and to add extra stable poses ("move-out" states) during task space
// expansion. CGAL stays inside this library's .cpp (it adds -frounding-math).
#include <memory>
#include <optional>
#include <vector>

#include "engine/core/rng.h"
#include "engine/geometry/pose.h"
#include "engine/geometry/shapes.h"
#include "engine/scene/scene.h"

namespace dash {

class PlacementRegion {
 public:
  PlacementRegion(const SceneSurface& surface);
  ~PlacementRegion();
  PlacementRegion(PlacementRegion&&) noexcept;
  PlacementRegion& operator=(PlacementRegion&&) noexcept;

  double z() const { return z_; }
  /// The box's footprint (at yaw about z) lies inside the polygon.
  bool supports(const BoxShape& box, double x, double y, double yaw) const;
  /// A random upright pose of `box` resting on the region, or nullopt after `attempts` tries.
  std::optional<Pose> sample(const BoxShape& box, Rng& rng, int attempts = 64) const;
  /// Like sample(), restricted to points within `radius` of `center` (x, y).
  std::optional<Pose> sampleNear(const BoxShape& box, const Vec3& center, double radius, Rng& rng,
                                 int attempts = 64) const;
  double area() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  double z_ = 0.0;
  double min_x_ = 0, max_x_ = 0, min_y_ = 0, max_y_ = 0;
};

}  // namespace dash
