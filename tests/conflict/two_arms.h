#pragma once
// Two UR5e arms of a generated sorting scene (2 robots, 2 objects) with their collision world: the
// fixture of the conflict tests that need real geometry but no plan.
#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scene/object_layout.h"

namespace dash::testing {

struct TwoArms {
  Scene scene = generateScenario("sorting", {{"robots", "2"}, {"objects", "2"}}, 1, RobotLibrary::loadDefault());
  CollisionWorld world{scene};
  CollisionContext context{world};
  ObjectLayout layout = ObjectLayout::atStart(scene);
};

}  // namespace dash::testing
