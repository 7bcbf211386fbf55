#pragma once
// What a motion is checked against: the moving robot's held object, the objects resting at that moment
// of the schedule, other robots standing still (when replanning around them), and the regions of the
// motion constraints of the history it belongs to (paper, "Query (Motion-extended Hypergraph)"). Roadmap
// validity depends on it, so a roadmap is told when it changes.
#include <vector>

#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"
#include "engine/scene/object_layout.h"

namespace dash {

struct MotionContext {
  HeldObject held;
  ObjectLayout layout;
  std::vector<RobotState> parked;  ///< other robots, fixed for the whole motion
  /// Regions p of the motion constraints C_M on this move: world boxes the robot's bodies and held
  /// object stay out of (engine/collision/region_queries.h).
  std::vector<Aabb> avoid;

  bool sameAs(const MotionContext& o) const;
};

}  // namespace dash
