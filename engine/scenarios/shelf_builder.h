#pragma once
// Shelf units of cubbies whose rear slots are fully blocked by the objects in front of them (the
// Shelf-wall and Stocking families). Each cubby is open at the front only: a board above (no top
// grasp), side panels (no grasp from the side), the back panel behind (no grasp from behind). Objects
// stand on narrow pedestals so the gripper, held horizontal with its fingers closing sideways, clears
// the cubby floor. Slots lie one behind the other at kSlotSpacing, closer than the gripper body's
// reach in front of the TCP (0.047 m + its 0.04 m radius), so any grasp of a rear slot passes through
// the slot in front of it. Pedestals rise by kPedestalStep from front to back: the gripper body
// (radius 0.04 about the TCP's height) reaching a slot then passes just over the pedestals in front
// of it, yet still through the cube standing on the next one.
#include <string>
#include <vector>

#include "engine/scenarios/layout_tools.h"
#include "engine/scenarios/scene_builder.h"

namespace dash::shelf {

inline constexpr double kCubbyWidth = 0.18;  ///< inside; gripper and wrist (radius 0.045) fit
/// Floor to the board above: the rear cube's top plus room for the gripper body above its TCP.
inline constexpr double kHeadroom = 0.035;
inline constexpr double kBoard = 0.01;           ///< boards and side panels
inline constexpr double kBaseHeight = 0.12;      ///< floor of the lowest level above the table
inline constexpr double kPedestalHeight = 0.03;  ///< front slot; each slot behind is kPedestalStep taller
inline constexpr double kPedestalStep = 0.03;
inline constexpr double kPedestalWidth = 0.03;    ///< narrower than the cube
inline constexpr double kPedestalSurface = 0.05;  ///< resting polygon on a pedestal (holds the 4 cm footprint)
inline constexpr double kSlotSpacing = 0.06;      ///< centre to centre, front to rear
inline constexpr double kFrontInset = 0.04;       ///< front slot centre behind the front edge
inline constexpr double kBackGap = 0.04;          ///< rear slot centre to the back of the cubby

/// One cube place in a cubby.
struct Slot {
  Vec3 p_W;  ///< cube centre
  int column = 0;
  int level = 0;
  int depth = 0;        ///< 0 = front
  std::string surface;  ///< id of its pedestal's resting surface
};

struct Unit {
  std::vector<Slot> slots;    ///< column-major: (column, level, depth) with depth fastest
  double depth = 0.0;         ///< back to front edge
  double width = 0.0;         ///< outside, side panel to side panel
  double height = 0.0;        ///< table to the top of the top board
  double cubby_height = 0.0;  ///< floor to the board above
  int columns = 0, levels = 0, depth_slots = 0;
  const Slot& slot(int column, int level, int depth_index) const;
};

/// Depth of a unit with `depth_slots` slots one behind the other.
double unitDepth(int depth_slots);
/// Pedestal height of slot `depth_index` (0 = front).
double pedestalHeight(int depth_index);
/// Floor to the board above in a unit with `depth_slots` slots one behind the other.
double cubbyHeight(int depth_slots);
/// Width of a unit with `columns` cubbies.
double unitWidth(int columns);

/// Adds a unit whose back lies on the line through `back.origin` across back.yaw, opening towards
/// back.yaw (the frame's x), centred on the origin sideways. Ids start with `prefix`.
Unit addUnit(SceneBuilder& builder, const std::string& prefix, const layout::WorkFrame& back, int columns, int levels,
             int depth_slots);

/// Yaw of objects in a unit that opens towards `back.yaw`: the cube's faces line up with the cubby.
inline double slotYaw(const layout::WorkFrame& back) { return back.yaw; }

}  // namespace dash::shelf
