#include "engine/scenarios/scene_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

#include "engine/robots/kinematics.h"

namespace dash {

namespace {

using Vec2 = Eigen::Vector2d;

constexpr std::uint32_t kRobotColour = 0x2b3a55;
constexpr std::uint32_t kSurfaceColour = 0x3b7dd8;
constexpr std::uint32_t kUnchangedColour = 0xe0a100;  ///< goal == start
constexpr std::uint32_t kFixedColour = 0x707070;
constexpr std::array<std::uint32_t, 12> kPalette = {0xe6194b, 0x3cb44b, 0x4363d8, 0xf58231, 0x911eb4, 0x42d4f4,
                                                    0xf032e6, 0x9a6324, 0x469990, 0x800000, 0x808000, 0x000075};
constexpr double kTallest = 1.5;  ///< obstacle height drawn darkest
constexpr double kUrBaseRadius = 0.075;
constexpr double kHomeTick = 0.12;

/// World to pixel mapping.
struct Canvas {
  RgbImage image;
  double x0 = 0.0, y1 = 0.0, scale = 1.0;  ///< left edge, top edge, pixels per metre

  Vec2 toPixel(const Vec2& p) const { return Vec2((p.x() - x0) * scale, (y1 - p.y()) * scale); }
  Vec2 toWorld(double px, double py) const { return Vec2(x0 + (px + 0.5) / scale, y1 - (py + 0.5) / scale); }

  /// Fills a convex polygon (any winding).
  void fillConvex(const std::vector<Vec2>& poly, std::uint32_t colour) {
    double xmin = 1e18, xmax = -1e18, ymin = 1e18, ymax = -1e18;
    std::vector<Vec2> px;
    for (const Vec2& p : poly) {
      px.push_back(toPixel(p));
      xmin = std::min(xmin, px.back().x());
      xmax = std::max(xmax, px.back().x());
      ymin = std::min(ymin, px.back().y());
      ymax = std::max(ymax, px.back().y());
    }
    for (int y = std::max(0, static_cast<int>(std::floor(ymin)));
         y <= std::min(image.height - 1, static_cast<int>(ymax)); ++y) {
      for (int x = std::max(0, static_cast<int>(std::floor(xmin)));
           x <= std::min(image.width - 1, static_cast<int>(xmax)); ++x) {
        const Vec2 c(x + 0.5, y + 0.5);
        int positive = 0, negative = 0;
        for (std::size_t i = 0; i < px.size(); ++i) {
          const Vec2& a = px[i];
          const Vec2& b = px[(i + 1) % px.size()];
          const double cross = (b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x());
          if (cross > 0) ++positive;
          if (cross < 0) ++negative;
        }
        if (positive == 0 || negative == 0) image.set(x, y, colour);
      }
    }
  }

  void line(const Vec2& a_W, const Vec2& b_W, std::uint32_t colour, int thickness = 1) {
    const Vec2 a = toPixel(a_W), b = toPixel(b_W);
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() * 2.0)));
    for (int i = 0; i <= steps; ++i) {
      const Vec2 p = a + (b - a) * (static_cast<double>(i) / steps);
      for (int dy = 0; dy < thickness; ++dy) {
        for (int dx = 0; dx < thickness; ++dx) {
          image.set(static_cast<int>(std::floor(p.x())) + dx, static_cast<int>(std::floor(p.y())) + dy, colour);
        }
      }
    }
  }

  void outline(const std::vector<Vec2>& poly, std::uint32_t colour, int thickness = 1) {
    for (std::size_t i = 0; i < poly.size(); ++i) line(poly[i], poly[(i + 1) % poly.size()], colour, thickness);
  }

  void disc(const Vec2& centre_W, double radius_W, std::uint32_t colour) {
    const Vec2 c = toPixel(centre_W);
    const double r = std::max(1.5, radius_W * scale);
    for (int y = static_cast<int>(c.y() - r) - 1; y <= static_cast<int>(c.y() + r) + 1; ++y) {
      for (int x = static_cast<int>(c.x() - r) - 1; x <= static_cast<int>(c.x() + r) + 1; ++x) {
        if (Vec2(x + 0.5 - c.x(), y + 0.5 - c.y()).norm() <= r) image.set(x, y, colour);
      }
    }
  }
};

/// Footprint of a box at pose X: the convex hull of its 8 corners projected on the ground.
std::vector<Vec2> footprint(const BoxShape& box, const Pose& X) {
  std::vector<Vec2> pts;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c(((i & 1) ? 0.5 : -0.5) * box.size.x(), ((i & 2) ? 0.5 : -0.5) * box.size.y(),
                 ((i & 4) ? 0.5 : -0.5) * box.size.z());
    const Vec3 w = X * c;
    pts.emplace_back(w.x(), w.y());
  }
  // Monotone chain hull.
  std::sort(pts.begin(), pts.end(),
            [](const Vec2& a, const Vec2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  auto cross = [](const Vec2& o, const Vec2& a, const Vec2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Vec2> hull(2 * pts.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], pts[i]) <= 0) --k;
    hull[k++] = pts[i];
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(hull[k - 2], hull[k - 1], pts[i - 1]) <= 0) --k;
    hull[k++] = pts[i - 1];
  }
  hull.resize(k > 1 ? k - 1 : k);
  return hull;
}

double topOf(const BoxShape& box, const Pose& X) {
  double top = -1e18;
  for (int i = 0; i < 8; ++i) {
    const Vec3 c(((i & 1) ? 0.5 : -0.5) * box.size.x(), ((i & 2) ? 0.5 : -0.5) * box.size.y(),
                 ((i & 4) ? 0.5 : -0.5) * box.size.z());
    top = std::max(top, (X * c).z());
  }
  return top;
}

std::uint32_t shade(double top) {
  const double t = std::clamp(top / kTallest, 0.0, 1.0);
  const auto v = static_cast<std::uint32_t>(std::lround(225.0 - 165.0 * std::sqrt(t)));
  return (v << 16) | (v << 8) | v;
}

/// Lighter version of a colour (for surfaces that belong to a group).
std::uint32_t lighten(std::uint32_t c, double f) {
  auto ch = [&](int shift) {
    const double v = static_cast<double>((c >> shift) & 0xffu);
    return static_cast<std::uint32_t>(std::lround(v + (255.0 - v) * f)) << shift;
  };
  return ch(16) | ch(8) | ch(0);
}

/// Gantry reach rectangle in the world (TCP x, y over the joint limits).
std::vector<Vec2> gantryReach(const SceneRobot& r) {
  const auto& lo = r.model->limits.position_min;
  const auto& hi = r.model->limits.position_max;
  std::vector<Vec2> out;
  for (const auto& [x, y] : {std::pair{lo[0], lo[1]}, {hi[0], lo[1]}, {hi[0], hi[1]}, {lo[0], hi[1]}}) {
    const Vec3 w = r.X_WB * Vec3(x, y, 0.0);
    out.emplace_back(w.x(), w.y());
  }
  return out;
}

int nearestRobot(const Scene& scene, const Vec3& p) {
  int best = -1;
  double best_d = 1e18;
  for (std::size_t r = 0; r < scene.robots.size(); ++r) {
    const double d = (scene.robots[r].X_WB.translation() - p).head<2>().norm();
    if (d < best_d - 1e-9) {
      best_d = d;
      best = static_cast<int>(r);
    }
  }
  return best;
}

/// Extent: obstacles, surfaces, robots (gantries: their reach), objects; plus the margin.
Eigen::AlignedBox2d sceneExtent(const Scene& scene, double margin) {
  Eigen::AlignedBox2d extent;
  for (const auto& o : scene.obstacles) {
    for (const Vec2& p : footprint(o.shape, o.X_WO)) extent.extend(p);
  }
  for (const auto& s : scene.surfaces) {
    for (const Vec2& p : s.polygon) extent.extend(p);
  }
  for (const auto& r : scene.robots) {
    extent.extend(Vec2(r.X_WB.translation().head<2>()));
    if (r.model->kinematics == KinematicsKind::kGantry) {
      for (const Vec2& p : gantryReach(r)) extent.extend(p);
    }
  }
  for (const auto& o : scene.objects) extent.extend(Vec2(o.X_WO_start.translation().head<2>()));
  if (extent.isEmpty()) extent.extend(Vec2::Zero());
  extent.min() -= Vec2::Constant(margin);
  extent.max() += Vec2::Constant(margin);
  return extent;
}

/// Obstacles, lowest first.
void drawObstacles(Canvas& canvas, const Scene& scene) {
  std::vector<std::size_t> order(scene.obstacles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return topOf(scene.obstacles[a].shape, scene.obstacles[a].X_WO) <
           topOf(scene.obstacles[b].shape, scene.obstacles[b].X_WO);
  });
  for (const std::size_t i : order) {
    const auto& o = scene.obstacles[i];
    const auto poly = footprint(o.shape, o.X_WO);
    canvas.fillConvex(poly, shade(topOf(o.shape, o.X_WO)));
    canvas.outline(poly, shade(topOf(o.shape, o.X_WO) + 0.3));
  }
}

/// Surfaces: outlined; "box_N" in robot N's colour. Those larger than `area_limit` (the table) are left out.
void drawSurfaces(Canvas& canvas, const Scene& scene, double area_limit) {
  for (const auto& s : scene.surfaces) {
    const Eigen::AlignedBox2d box = [&] {
      Eigen::AlignedBox2d b;
      for (const Vec2& p : s.polygon) b.extend(p);
      return b;
    }();
    if (box.volume() > area_limit) continue;
    std::uint32_t colour = kSurfaceColour;
    if (s.id.rfind("box_", 0) == 0) {
      const int n = std::atoi(s.id.c_str() + 4);
      colour = kPalette[static_cast<std::size_t>(n) % kPalette.size()];
      canvas.fillConvex(s.polygon, lighten(colour, 0.8));
    }
    canvas.outline(s.polygon, colour, 2);
  }
}

/// A gantry: its reach, and its bodies (bridge, carriage, ram, tool) at home.
void drawGantry(Canvas& canvas, const SceneRobot& robot, std::uint32_t colour) {
  canvas.outline(gantryReach(robot), colour, 2);
  std::vector<Pose> frames(robot.model->bodies.size());
  bodyFrames(*robot.model, robot.X_WB, robot.home, frames);
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const CollisionBody& body = robot.model->bodies[i];
    if (body.kind != CollisionBody::Kind::kBox) continue;
    Pose X = frames[i];
    X.translation() += X.linear() * body.box_center;
    const auto poly = footprint(BoxShape{.size = 2.0 * body.box_half_extents}, X);
    canvas.fillConvex(poly, lighten(colour, 0.45));
    canvas.outline(poly, colour);
  }
}

void drawRobots(Canvas& canvas, const Scene& scene) {
  for (std::size_t r = 0; r < scene.robots.size(); ++r) {
    const SceneRobot& robot = scene.robots[r];
    const Vec2 base = robot.X_WB.translation().head<2>();
    if (robot.model->kinematics == KinematicsKind::kGantry) {
      drawGantry(canvas, robot, kPalette[r % kPalette.size()]);
      continue;
    }
    const Vec3 tcp = forwardKinematics(*robot.model, robot.X_WB, robot.home).X_WT.translation();
    const Vec2 dir = (Vec2(tcp.head<2>()) - base).normalized();
    canvas.disc(base, kUrBaseRadius, kRobotColour);
    canvas.line(base, base + dir * (kUrBaseRadius + kHomeTick), kRobotColour, 3);
    canvas.disc(base, 0.35 * kUrBaseRadius, kPalette[r % kPalette.size()]);
  }
}

/// Objects: goals (outlined) under starts (filled).
void drawObjects(Canvas& canvas, const Scene& scene) {
  auto colourOf = [&](const SceneObject& o) {
    if (o.fixed) return kFixedColour;
    if (!o.X_WO_goal || translationDistance(*o.X_WO_goal, o.X_WO_start) < 1e-3) return kUnchangedColour;
    const int r = nearestRobot(scene, o.X_WO_goal->translation());
    return kPalette[static_cast<std::size_t>(std::max(r, 0)) % kPalette.size()];
  };
  for (const auto& o : scene.objects) {
    if (!o.X_WO_goal || o.fixed) continue;
    canvas.outline(footprint(o.shape, *o.X_WO_goal), colourOf(o), 2);
  }
  for (const auto& o : scene.objects) {
    const auto poly = footprint(o.shape, o.X_WO_start);
    canvas.fillConvex(poly, colourOf(o));
    canvas.outline(poly, 0x202020);
  }
}

}  // namespace

RgbImage renderScene(const Scene& scene, const PictureOptions& options) {
  const Eigen::AlignedBox2d extent = sceneExtent(scene, options.margin);
  const Vec2 size = extent.sizes();
  Canvas canvas;
  canvas.scale = options.max_side_pixels / std::max(size.x(), size.y());
  canvas.x0 = extent.min().x();
  canvas.y1 = extent.max().y();
  canvas.image = RgbImage(std::max(1, static_cast<int>(std::lround(size.x() * canvas.scale))),
                          std::max(1, static_cast<int>(std::lround(size.y() * canvas.scale))), 0xff);
  drawObstacles(canvas, scene);
  drawSurfaces(canvas, scene, 0.5 * size.x() * size.y());
  drawRobots(canvas, scene);
  drawObjects(canvas, scene);
  return canvas.image;
}

}  // namespace dash
