#include "engine/scenarios/layout_tools.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/core/check.h"
#include "engine/scenarios/portable_random.h"
#include "engine/scenarios/scene_builder.h"

namespace dash::layout {

Vec2 WorkFrame::toWorld(double out, double left) const { return origin + rotate2(Vec2(out, left), yaw); }

double WorkFrame::ur5eBaseYaw() const { return yaw + std::numbers::pi; }

std::vector<Vec2> gridSlots(const WorkFrame& frame, const AreaSpec& area, Side side, double pitch,
                            const std::function<bool(const Vec2&)>& keep) {
  std::vector<Vec2> out;
  const int n = static_cast<int>(std::ceil(area.max_reach / pitch));
  // Rows from the base outwards, each row from the middle line sideways: nearer slots come first.
  for (int i = -n; i <= n; ++i) {
    for (int k = 0; k <= n; ++k) {
      const double o = i * pitch;
      const double s = area.min_side + 0.5 * pitch + k * pitch;  // first column half a pitch off the line
      const double l = side == Side::kLeft ? s : -s;
      const double reach = std::hypot(o, l);
      if (reach < area.min_reach || reach > area.max_reach || o < area.min_out) continue;
      const Vec2 p = frame.toWorld(o, l);
      if (keep && !keep(p)) continue;
      out.push_back(p);
    }
  }
  return out;
}

std::vector<Vec2> compactCluster(const std::vector<Vec2>& slots, int count, Rng& rng) {
  DASH_DEMAND(count >= 0 && static_cast<std::size_t>(count) <= slots.size());
  if (count == 0) return {};
  const Vec2 centre =
      slots[static_cast<std::size_t>(portable::integer(rng, 0, static_cast<std::int64_t>(slots.size()) - 1))];
  std::vector<std::size_t> order(slots.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return (slots[a] - centre).squaredNorm() < (slots[b] - centre).squaredNorm();
  });
  std::vector<Vec2> out;
  for (int i = 0; i < count; ++i) out.push_back(slots[order[static_cast<std::size_t>(i)]]);
  return out;
}

std::vector<Vec2> boundingRectangle(const WorkFrame& frame, const std::vector<Vec2>& points, double margin) {
  DASH_DEMAND(!points.empty());
  double o_min = 1e9, o_max = -1e9, l_min = 1e9, l_max = -1e9;
  for (const Vec2& p : points) {
    const Vec2 local = rotate2(p - frame.origin, -frame.yaw);
    o_min = std::min(o_min, local.x());
    o_max = std::max(o_max, local.x());
    l_min = std::min(l_min, local.y());
    l_max = std::max(l_max, local.y());
  }
  o_min -= margin;
  o_max += margin;
  l_min -= margin;
  l_max += margin;
  return {frame.toWorld(o_min, l_min), frame.toWorld(o_max, l_min), frame.toWorld(o_max, l_max),
          frame.toWorld(o_min, l_max)};
}

double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

}  // namespace dash::layout
