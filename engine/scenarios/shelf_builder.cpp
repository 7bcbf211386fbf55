#include "engine/scenarios/shelf_builder.h"

#include "engine/core/check.h"

namespace dash::shelf {

namespace {
inline std::size_t at(int i) { return static_cast<std::size_t>(i); }
}  // namespace

const Slot& Unit::slot(int column, int level, int depth_index) const {
  DASH_DEMAND(column >= 0 && column < columns && level >= 0 && level < levels && depth_index >= 0 &&
              depth_index < depth_slots);
  return slots[at((column * levels + level) * depth_slots + depth_index)];
}

double unitDepth(int depth_slots) { return kFrontInset + (depth_slots - 1) * kSlotSpacing + kBackGap; }

double pedestalHeight(int depth_index) { return kPedestalHeight + depth_index * kPedestalStep; }

double cubbyHeight(int depth_slots) { return pedestalHeight(depth_slots - 1) + layout::kCube + kHeadroom; }

double unitWidth(int columns) { return columns * (kCubbyWidth + kBoard) + kBoard; }

Unit addUnit(SceneBuilder& builder, const std::string& prefix, const layout::WorkFrame& back, int columns, int levels,
             int depth_slots) {
  Unit u;
  u.columns = columns;
  u.levels = levels;
  u.depth_slots = depth_slots;
  u.depth = unitDepth(depth_slots);
  u.width = unitWidth(columns);
  u.cubby_height = cubbyHeight(depth_slots);
  const double pitch_z = u.cubby_height + kBoard;
  u.height = kBaseHeight + levels * pitch_z;
  const double yaw = back.yaw;
  auto world = [&](double out, double left, double z) {
    const layout::Vec2 p = back.toWorld(out, left);
    return Vec3(p.x(), p.y(), z);
  };
  // Solid base under the lowest level, then the board above each level, then the side panels.
  builder.addBox(prefix + "base", Vec3(u.depth, u.width, kBaseHeight), world(0.5 * u.depth, 0.0, 0.5 * kBaseHeight),
                 yaw);
  for (int l = 0; l < levels; ++l) {
    const double z = kBaseHeight + l * pitch_z + u.cubby_height + 0.5 * kBoard;
    builder.addBox(prefix + "board_" + std::to_string(l), Vec3(u.depth, u.width, kBoard), world(0.5 * u.depth, 0.0, z),
                   yaw);
  }
  const double panel_height = levels * pitch_z - kBoard;
  for (int c = 0; c <= columns; ++c) {
    const double left = -0.5 * u.width + 0.5 * kBoard + c * (kCubbyWidth + kBoard);
    builder.addBox(prefix + "panel_" + std::to_string(c), Vec3(u.depth, kBoard, panel_height),
                   world(0.5 * u.depth, left, kBaseHeight + 0.5 * panel_height), yaw);
  }
  for (int c = 0; c < columns; ++c) {
    const double left = -0.5 * u.width + kBoard + (c + 0.5) * (kCubbyWidth + kBoard) - 0.5 * kBoard;
    for (int l = 0; l < levels; ++l) {
      const double floor = kBaseHeight + l * pitch_z;
      for (int d = 0; d < depth_slots; ++d) {
        const double out = u.depth - kFrontInset - d * kSlotSpacing;
        const std::string id = prefix + "c" + std::to_string(c) + "_l" + std::to_string(l) + "_d" + std::to_string(d);
        const double h = pedestalHeight(d);
        builder.addBox(id + "_pedestal", Vec3(kPedestalWidth, kPedestalWidth, h), world(out, left, floor + 0.5 * h),
                       yaw);
        builder.addRectSurface(id, floor + h, back.toWorld(out, left), layout::Vec2(kPedestalSurface, kPedestalSurface),
                               yaw);
        u.slots.push_back({.p_W = world(out, left, floor + h + 0.5 * layout::kCube),
                           .column = c,
                           .level = l,
                           .depth = d,
                           .surface = id});
      }
    }
  }
  return u;
}

}  // namespace dash::shelf
