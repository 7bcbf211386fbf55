// Shelf-wall and Stocking (Lazy-DaSH, Sec. "Shelf-wall" and "Stocking"). Both stand UR5e arms in
// front of shelf units built by shelf_builder.h, with a tall panel behind the cubbies that no arm
// reaches over: objects cross it only by a handover round its end. Layout and rules:
// engine/scenarios/README.md.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "engine/scenarios/layout_tools.h"
#include "engine/scenarios/portable_random.h"
#include "engine/scenarios/scenario_families.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scenarios/shelf_builder.h"

namespace dash {

namespace {

using layout::Vec2;

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

constexpr double kRobotToShelf = 0.60;     ///< base axis to the shelf front edge (nearer, the arm folds
                                           ///< so far to reach in that it cannot back out)
constexpr double kFeederToPanel = 0.45;    ///< stocking: the feeder base axis to the back panel (it
                                           ///< reaches no cubby; nearer, it meets the stocker round the end)
constexpr double kRowSpacing = 1.2;        ///< robots side by side along a shelf
constexpr double kDivider = 0.02;          ///< thickness of the panel behind the cubbies
constexpr double kDividerHeight = 1.5;     ///< out of reach over the top
constexpr double kDividerEndMargin = 0.1;  ///< divider beyond the outermost cubby
constexpr double kTableMargin = 0.3;
constexpr double kTableThickness = 0.05;
constexpr double kOtherRobotClearance = 1.0;  ///< start slots out of other robots' top-grasp reach
constexpr double kStartPitch = 0.08;
constexpr int kMaxColumnsShelfWall = 3;
constexpr int kMaxColumnsStocking = 4;
// Stocking staging posts: cubes on them can be grasped from the side (as they come out of the shelf)
// and from the top.
constexpr double kStagingPostHeight = 0.10;
constexpr double kStagingRadius = 0.5;
constexpr double kStagingSurface = 0.05;

const Vec3 kCubeSize(layout::kCube, layout::kCube, layout::kCube);

/// Handovers round the end of a divider: look farther sideways than between neighbours in the open.
HandoverSearch shelfHandoverSearch() {
  HandoverSearch s;
  s.across = {0.0, -0.15, 0.15, -0.3, 0.3, -0.45, 0.45, -0.55, 0.55, -0.65, 0.65, -0.75, 0.75};
  return s;
}

/// A cluster of `count` start slots on the table behind robot frame f.
std::vector<Vec2> startCluster(const layout::WorkFrame& f, int count, const std::vector<layout::WorkFrame>& robots,
                               double table_half_x, double table_half_y, Rng& rng) {
  auto keep = [&](const Vec2& p) {
    for (const auto& r : robots) {
      if ((r.origin - f.origin).norm() > 1e-9 && (p - r.origin).norm() < kOtherRobotClearance) return false;
    }
    return std::abs(p.x()) < table_half_x - 0.1 && std::abs(p.y()) < table_half_y - 0.1;
  };
  layout::AreaSpec area;
  area.min_out = 0.15;  // behind the robot, away from the shelf
  std::vector<Vec2> slots = layout::gridSlots(f, area, layout::Side::kLeft, kStartPitch, keep);
  const std::vector<Vec2> right = layout::gridSlots(f, area, layout::Side::kRight, kStartPitch, keep);
  slots.insert(slots.end(), right.begin(), right.end());
  if (static_cast<int>(slots.size()) < count) {
    throw ScenarioError("no room for " + std::to_string(count) + " start objects behind one robot (room for " +
                        std::to_string(slots.size()) + ")");
  }
  std::vector<Vec2> cluster = layout::compactCluster(slots, count, rng);
  portable::shuffle(cluster, rng);
  return cluster;
}

Pose onTable(const Vec2& p, double yaw) { return yawPose(Vec3(p.x(), p.y(), 0.5 * layout::kCube), yaw); }

}  // namespace

// ---- Shelf-wall ----------------------------------------------------------------------------------
// k = robots / 2 robots stand in a row on each side of a long double-sided shelf whose middle panel is
// a wall. Each robot has its own block of cubbies on its face. An object bound for a cubby of robot j
// on one side starts behind the robot at the mirrored place on the other side, so it crosses the wall
// round an end: 1 handover with 2 robots, at least 2 with 4 or more. In each cubby the rear object
// must go in before the front one.
namespace {

/// Shelf-wall's layout before any random choice: faces, cubbies, robot frames, table and divider.
struct ShelfWallGeometry {
  int k = 0;                    ///< robots per side
  int faces = 0;                ///< one per robot: 0..k-1 south, k..2k-1 north
  std::vector<int> per_face;    ///< objects per face, round robin
  int columns = 0, levels = 0;  ///< cubbies of each face
  double divider_half = 0.0, table_half_x = 0.0, table_half_y = 0.0;
  std::vector<layout::WorkFrame> robot_frames;
  /// The face on the other side of the wall that a face's objects start behind.
  int mirror(int face) const { return face < k ? k + (k - 1 - face) : (k - 1 - (face - k)); }
};

ShelfWallGeometry shelfWallGeometry(int robots, int objects) {
  ShelfWallGeometry g;
  g.k = robots / 2;
  g.faces = robots;
  const int k = g.k;
  // Objects per face, round robin; two per cubby (rear, then front).
  g.per_face.assign(at(g.faces), 0);
  for (int i = 0; i < objects; ++i) ++g.per_face[at(i % g.faces)];
  const int cubbies = (*std::max_element(g.per_face.begin(), g.per_face.end()) + 1) / 2;
  g.columns = std::min(kMaxColumnsShelfWall, cubbies);
  g.levels = (cubbies + g.columns - 1) / g.columns;

  const double depth = shelf::unitDepth(2);
  const double width = shelf::unitWidth(g.columns);
  const double robot_y = 0.5 * kDivider + depth + kRobotToShelf;
  std::vector<double> xs;
  for (int j = 0; j < k; ++j) xs.push_back((j - 0.5 * (k - 1)) * kRowSpacing);
  g.divider_half = xs.back() + 0.5 * width + kDividerEndMargin;
  g.table_half_x = g.divider_half + 1.0;
  g.table_half_y = robot_y + layout::AreaSpec{}.max_reach + kTableMargin;

  // Faces 0..k-1 on the south side (robots at -y), k..2k-1 on the north side.
  for (int side = 0; side < 2; ++side) {
    const double sign = side == 0 ? -1.0 : 1.0;
    for (int j = 0; j < k; ++j) {
      g.robot_frames.push_back({.origin = Vec2(xs[at(j)], sign * robot_y), .yaw = sign * 0.5 * std::numbers::pi});
    }
  }
  return g;
}

}  // namespace

GeneratedLayout generateShelfWall(const FamilyInput& in) {
  const int robots = in.params.get("robots");
  const int objects = in.params.get("objects");
  const ShelfWallGeometry g = shelfWallGeometry(robots, objects);
  const int k = g.k, faces = g.faces, columns = g.columns, levels = g.levels;
  const double table_half_x = g.table_half_x, table_half_y = g.table_half_y, divider_half = g.divider_half;
  const std::vector<layout::WorkFrame>& robot_frames = g.robot_frames;
  const std::vector<int>& per_face = g.per_face;
  auto mirror = [&](int face) { return g.mirror(face); };

  SceneBuilder b(in.library, sceneName(in, "r" + std::to_string(robots) + "-o" + std::to_string(objects)),
                 generatorRecord(in));
  for (int r = 0; r < robots; ++r) {
    const auto& f = robot_frames[at(r)];
    b.addRobot("ur5e_" + std::to_string(r), layout::kUr5eModel, Vec3(f.origin.x(), f.origin.y(), 0.0), f.ur5eBaseYaw(),
               layout::kUr5eHome, {"grasp"});
  }
  b.addBox("table", Vec3(2.0 * table_half_x, 2.0 * table_half_y, kTableThickness), Vec3(0, 0, -0.5 * kTableThickness));
  b.addBox("divider", Vec3(2.0 * divider_half, kDivider, kDividerHeight), Vec3(0, 0, 0.5 * kDividerHeight));
  b.addRectSurface("table_top", 0.0, Vec2::Zero(), Vec2(2.0 * table_half_x, 2.0 * table_half_y));
  std::vector<shelf::Unit> units;
  for (int face = 0; face < faces; ++face) {
    const auto& rf = robot_frames[at(face)];
    const double sign = face < k ? -1.0 : 1.0;
    const layout::WorkFrame back{.origin = Vec2(rf.origin.x(), sign * 0.5 * kDivider), .yaw = rf.yaw};
    units.push_back(shelf::addUnit(b, "shelf_" + std::to_string(face) + "_", back, columns, levels, 2));
  }

  // Start clusters: each robot holds the objects of its mirrored face.
  std::vector<std::vector<Vec2>> clusters(at(faces));
  for (int face = 0; face < faces; ++face) {
    clusters[at(face)] = startCluster(robot_frames[at(mirror(face))], per_face[at(face)], robot_frames, table_half_x,
                                      table_half_y, in.rng);
  }
  // Which cubbies of a face are used: a random choice among them.
  GeneratedLayout out;
  std::vector<int> face_count(at(faces), 0);
  std::vector<std::vector<int>> cubby_order(at(faces));
  for (int face = 0; face < faces; ++face) {
    for (int c = 0; c < columns * levels; ++c) cubby_order[at(face)].push_back(c);
    portable::shuffle(cubby_order[at(face)], in.rng);
  }
  std::vector<int> rear_object;  // per object: the rear object of its cubby if it is a front one, else -1
  for (int i = 0; i < objects; ++i) {
    const int face = i % faces;
    const int m = face_count[at(face)]++;
    const int cubby = cubby_order[at(face)][at(m / 2)];
    const shelf::Slot& slot = units[at(face)].slot(cubby / levels, cubby % levels, m % 2 == 0 ? 1 : 0);
    const double yaw = robot_frames[at(face)].yaw;
    const Vec2 start = clusters[at(face)][at(m)];
    const int index = b.addObject("obj_" + std::to_string(i), kCubeSize,
                                  onTable(start, robot_frames[at(mirror(face))].yaw), yawPose(slot.p_W, yaw));
    // Front objects (odd m) block the rear one placed just before them in the same cubby.
    if (m % 2 == 1) {
      const int rear = index - faces;  // the previous object of this face
      out.validation.blocked.push_back({.object = rear, .at_goal = true, .blockers = {index}});
    }
  }
  out.scene = b.build();
  out.validation.handover_search = shelfHandoverSearch();
  return out;
}

// ---- Stocking ------------------------------------------------------------------------------------
// A stocker arm in front of a one-sided shelf, a feeder arm behind its back panel. Each cubby holds
// `layers` slots one behind the other: existing items in the front ones (their goal is where they
// stand), and the rear one is where a new item goes. The new items start behind the feeder, so each
// comes round the panel's end by a handover; the stocker must first move the existing items of the
// cubby out to staging posts (front first) and put them back in reverse order.
GeneratedLayout generateStocking(const FamilyInput& in) {
  const int layers = in.params.get("layers");
  const int objects = in.params.get("objects");
  const int cubbies = (objects + layers - 1) / layers;
  const int columns = std::min(kMaxColumnsStocking, cubbies);
  const int levels = (cubbies + columns - 1) / columns;
  const double depth = shelf::unitDepth(layers);
  const double width = shelf::unitWidth(columns);
  const double divider_half = 0.5 * width + kDividerEndMargin;
  const double pi = std::numbers::pi;
  const layout::WorkFrame stocker{.origin = Vec2(0.0, -(depth + kRobotToShelf)), .yaw = -0.5 * pi};
  const layout::WorkFrame feeder{.origin = Vec2(0.0, kDivider + kFeederToPanel), .yaw = 0.5 * pi};
  const double table_half_x = divider_half + 1.0;
  const double table_y_min = stocker.origin.y() - layout::AreaSpec{}.max_reach - kTableMargin;
  const double table_y_max = feeder.origin.y() + layout::AreaSpec{}.max_reach + kTableMargin;
  const double table_half_y = std::max(-table_y_min, table_y_max);

  SceneBuilder b(in.library, sceneName(in, "l" + std::to_string(layers) + "-o" + std::to_string(objects)),
                 generatorRecord(in));
  b.addRobot("ur5e_0", layout::kUr5eModel, Vec3(stocker.origin.x(), stocker.origin.y(), 0.0), stocker.ur5eBaseYaw(),
             layout::kUr5eHome, {"grasp"});
  b.addRobot("ur5e_1", layout::kUr5eModel, Vec3(feeder.origin.x(), feeder.origin.y(), 0.0), feeder.ur5eBaseYaw(),
             layout::kUr5eHome, {"grasp"});
  b.addBox("table", Vec3(2.0 * table_half_x, 2.0 * table_half_y, kTableThickness), Vec3(0, 0, -0.5 * kTableThickness));
  b.addBox("back_panel", Vec3(2.0 * divider_half, kDivider, kDividerHeight),
           Vec3(0.0, 0.5 * kDivider, 0.5 * kDividerHeight));
  b.addRectSurface("table_top", 0.0, Vec2::Zero(), Vec2(2.0 * table_half_x, 2.0 * table_half_y));
  const shelf::Unit unit =
      shelf::addUnit(b, "shelf_", {.origin = Vec2::Zero(), .yaw = -0.5 * pi}, columns, levels, layers);

  // Staging posts behind the stocker: one more than the items moved out of one cubby.
  const int posts = layers;
  for (int i = 0; i < posts; ++i) {
    const double angle = (posts == 1 ? 0.0 : -0.45 * pi + 0.9 * pi * i / (posts - 1)) * 0.75;
    const Vec2 p = stocker.toWorld(kStagingRadius * std::cos(angle), kStagingRadius * std::sin(angle));
    const std::string id = "staging_" + std::to_string(i);
    b.addBox(id + "_post", Vec3(shelf::kPedestalWidth, shelf::kPedestalWidth, kStagingPostHeight),
             Vec3(p.x(), p.y(), 0.5 * kStagingPostHeight), stocker.yaw);
    b.addRectSurface(id, kStagingPostHeight, p, Vec2(kStagingSurface, kStagingSurface), stocker.yaw);
  }

  // Cubbies in a random order; new items start in a cluster behind the feeder.
  std::vector<int> order;
  for (int c = 0; c < columns * levels; ++c) order.push_back(c);
  portable::shuffle(order, in.rng);
  const std::vector<Vec2> starts = startCluster(feeder, cubbies, {stocker, feeder}, table_half_x, table_half_y, in.rng);

  GeneratedLayout out;
  int created = 0;
  for (int n = 0; n < cubbies; ++n) {
    const int cubby = order[at(n)];
    const int in_cubby = std::min(layers, objects - n * layers);  // the last cubby may hold fewer
    // Existing items fill the front slots; the new item goes behind them, in slot in_cubby - 1.
    std::vector<int> existing;  // front first
    for (int d = 0; d + 1 < in_cubby; ++d) {
      const shelf::Slot& slot = unit.slot(cubby / levels, cubby % levels, d);
      const Pose X = yawPose(slot.p_W, stocker.yaw);
      existing.push_back(b.addObject("item_" + std::to_string(created++), kCubeSize, X, X));
    }
    const shelf::Slot& rear = unit.slot(cubby / levels, cubby % levels, in_cubby - 1);
    const int fresh = b.addObject("new_" + std::to_string(n), kCubeSize, onTable(starts[at(n)], feeder.yaw),
                                  yawPose(rear.p_W, stocker.yaw));
    // Every slot is blocked by the items in front of it, at the start and at the goal.
    for (std::size_t d = 1; d < existing.size(); ++d) {
      const std::vector<int> front(existing.begin(), existing.begin() + static_cast<std::ptrdiff_t>(d));
      out.validation.blocked.push_back({.object = existing[d], .at_goal = false, .blockers = front});
      out.validation.blocked.push_back({.object = existing[d], .at_goal = true, .blockers = front});
    }
    if (!existing.empty()) out.validation.blocked.push_back({.object = fresh, .at_goal = true, .blockers = existing});
  }
  out.scene = b.build();
  out.validation.handover_search = shelfHandoverSearch();
  return out;
}

}  // namespace dash
