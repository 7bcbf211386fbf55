#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "tests/common/robot_library.h"

namespace dash::test {

using KeyValues = std::vector<std::pair<std::string, std::string>>;

inline GeneratedScenario generate(const std::string& family, const KeyValues& kv, std::uint64_t seed) {
  const ScenarioParams params = resolveParams(family, scenarioFamily(family).params, kv);
  return generateScenarioDetailed(family, params, seed, library());
}

/// Robots an object starts with / ends with, from the report.
inline const ObjectTransfer* transferOf(const GeneratedScenario& g, int object) {
  for (const auto& t : g.report.transfers) {
    if (t.object == object) return &t;
  }
  return nullptr;
}

}  // namespace dash::test
