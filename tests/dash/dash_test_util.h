#pragma once
// Scenes and helpers shared by the DaSH tests.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/dash/dash_params.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/scene/scene.h"

namespace dash::test {

inline std::shared_ptr<const RobotLibrary> dashLibrary() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib;
}

/// A generated scene: `family` with key=value overrides and a seed (as `dashbench scenario`).
inline Scene dashScene(const std::string& family, const std::vector<std::pair<std::string, std::string>>& kv,
                       std::uint64_t seed = 1) {
  return generateScenario(family, kv, seed, dashLibrary());
}

/// DaSH with a scheduler that has little room (at most 2 s of delay per transition, no composite
/// replanning): conflicts it would have repaired go to CBS-MP's constraint tree.
inline DashParams littleRoomScheduler() {
  DashParams params;
  params.scheduler.max_delay = 2.0;
  params.scheduler.composite_attempts = 0;
  return params;
}

}  // namespace dash::test
