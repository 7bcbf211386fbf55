#include "engine/placement/placement_region.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>

#include <cmath>

namespace dash {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Polygon = CGAL::Polygon_2<Kernel>;

struct PlacementRegion::Impl {
  Polygon polygon;
};

PlacementRegion::PlacementRegion(const SceneSurface& surface) : impl_(std::make_unique<Impl>()), z_(surface.z) {
  for (const auto& p : surface.polygon) impl_->polygon.push_back(Kernel::Point_2(p.x(), p.y()));
  if (impl_->polygon.is_clockwise_oriented()) impl_->polygon.reverse_orientation();
  const auto box = impl_->polygon.bbox();
  min_x_ = box.xmin();
  max_x_ = box.xmax();
  min_y_ = box.ymin();
  max_y_ = box.ymax();
}

PlacementRegion::~PlacementRegion() = default;
PlacementRegion::PlacementRegion(PlacementRegion&&) noexcept = default;
PlacementRegion& PlacementRegion::operator=(PlacementRegion&&) noexcept = default;

bool PlacementRegion::supports(const BoxShape& box, double x, double y, double yaw) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double hx = 0.5 * box.size.x(), hy = 0.5 * box.size.y();
  for (int sx : {-1, 1})
    for (int sy : {-1, 1}) {
      const double px = x + c * sx * hx - s * sy * hy;
      const double py = y + s * sx * hx + c * sy * hy;
      if (impl_->polygon.bounded_side(Kernel::Point_2(px, py)) == CGAL::ON_UNBOUNDED_SIDE) return false;
    }
  return true;
}

std::optional<Pose> PlacementRegion::sampleNear(const BoxShape& box, const Vec3& center, double radius, Rng& rng,
                                                int attempts) const {
  const double lo_x = std::max(min_x_, center.x() - radius), hi_x = std::min(max_x_, center.x() + radius);
  const double lo_y = std::max(min_y_, center.y() - radius), hi_y = std::min(max_y_, center.y() + radius);
  if (lo_x > hi_x || lo_y > hi_y) return std::nullopt;
  for (int i = 0; i < attempts; ++i) {
    const double x = rng.uniform(lo_x, hi_x), y = rng.uniform(lo_y, hi_y);
    if (std::hypot(x - center.x(), y - center.y()) > radius) continue;
    if (!supports(box, x, y, 0.0)) continue;
    return makePose(Vec3(x, y, z_ + 0.5 * box.size.z()));
  }
  return std::nullopt;
}

std::optional<Pose> PlacementRegion::sample(const BoxShape& box, Rng& rng, int attempts) const {
  const Vec3 center(0.5 * (min_x_ + max_x_), 0.5 * (min_y_ + max_y_), z_);
  return sampleNear(box, center, std::hypot(max_x_ - min_x_, max_y_ - min_y_), rng, attempts);
}

double PlacementRegion::area() const { return std::abs(CGAL::to_double(impl_->polygon.area())); }

}  // namespace dash
