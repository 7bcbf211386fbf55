#pragma once
// Small layout helpers shared by the family generators: robot-local work areas on a table, slot grids
// in them, compact clusters, and the constants of the UR5e + Hand-E setup the families are built for.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "engine/core/rng.h"

namespace dash::layout {

using Vec2 = Eigen::Vector2d;

inline constexpr double kCube = 0.04;  ///< edge of the objects (4 cm cubes)
/// UR5e home: upper arm up, forearm and tool over the area behind the base (the arm points along the
/// base's -x axis at q = 0), TCP 0.49 m out and 0.33 m up. Robots are turned so that this is their
/// own work area, away from the teammates.
inline const std::vector<double> kUr5eHome = {0.0, -1.5708, 1.5708, -1.5708, -1.5708, 0.0};
inline constexpr const char* kUr5eModel = "ur5e";

/// A robot's planar work frame: origin at its base, x pointing "out" (where its own area is), y to
/// its left.
struct WorkFrame {
  Vec2 origin = Vec2::Zero();
  double yaw = 0.0;  ///< direction of x in the world
  Vec2 toWorld(double out, double left) const;
  /// Base yaw for a UR5e whose home pose should point along this frame's x.
  double ur5eBaseYaw() const;
};

/// Where slots may lie in a work frame: a ring sector (distance from the base), how far in front of
/// the base they may reach (out >= min_out) and which side (left > min_side or right < -min_side).
struct AreaSpec {
  double min_reach = 0.40;
  double max_reach = 0.78;
  double min_out = -0.05;
  double min_side = 0.05;
};

enum class Side { kLeft, kRight };

/// Grid points at spacing `pitch` (grid aligned with the frame) inside the area on `side`, in a fixed
/// order, that also satisfy `keep` (world x, y).
std::vector<Vec2> gridSlots(const WorkFrame& frame, const AreaSpec& area, Side side, double pitch,
                            const std::function<bool(const Vec2&)>& keep);

/// `count` slots close together: the nearest ones to a random slot (ties by order). Requires
/// count <= slots.size().
std::vector<Vec2> compactCluster(const std::vector<Vec2>& slots, int count, Rng& rng);

/// Corners (counter-clockwise) of the frame-aligned rectangle around `points`, grown by `margin`.
std::vector<Vec2> boundingRectangle(const WorkFrame& frame, const std::vector<Vec2>& points, double margin);

/// Distance from p to the segment a-b.
double segmentDistance(const Vec2& p, const Vec2& a, const Vec2& b);

}  // namespace dash::layout
