#pragma once
// What a motion is checked against: the moving robot's held object, the objects resting at that moment
// of the schedule, and other robots standing still (when replanning around them). Roadmap validity
// depends on it, so a roadmap is told when it changes.
#include <vector>

#include "engine/collision/collision_state.h"
#include "engine/scene/object_layout.h"

namespace dash {

struct MotionContext {
  HeldObject held;
  ObjectLayout layout;
  std::vector<RobotState> parked;  ///< other robots, fixed for the whole motion

  bool sameAs(const MotionContext& o) const;
};

}  // namespace dash
