#pragma once
// A generated scene (seed 1) with its task layer's first task plan and a motion layer on it: the
// fixture of the motion tests that need a real plan.
#include <string>
#include <utility>
#include <vector>

#include "engine/events/memory_sink.h"
#include "engine/motion/motion_layer.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/task/task_layer.h"

namespace dash::testing {

struct FirstTaskPlan {
  FirstTaskPlan(const std::string& family, const std::vector<std::pair<std::string, std::string>>& params)
      : scene(generateScenario(family, params, 1, RobotLibrary::loadDefault())) {}
  Scene scene;
  CollisionWorld world{scene};
  CollisionContext context{world};
  log::MemorySink sink;
  log::EventEmitter emitter{&sink};
  TaskLayer task{scene, world, context, emitter, 1};
  MotionLayer motion{world, context, emitter};
  TaskLayerResult layer = task.plan(Deadline(120));
};

}  // namespace dash::testing
