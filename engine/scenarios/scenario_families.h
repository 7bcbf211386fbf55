#pragma once
// The family generators behind scenario_registry.h (internal to engine/scenarios). Each makes one
// layout from the random stream it is given and says how to validate it; the registry retries with
// derived seeds when validation fails.
#include <cstdint>
#include <memory>
#include <string>

#include "engine/core/rng.h"
#include "engine/scenarios/scenario_params.h"
#include "engine/scenarios/scenario_validation.h"
#include "engine/scene/scene.h"

namespace dash {

struct FamilyInput {
  std::string family;
  const ScenarioParams& params;
  std::uint64_t seed;  ///< the caller's seed, recorded in the scene
  Rng& rng;            ///< this attempt's random stream
  std::shared_ptr<const RobotLibrary> library;
};

struct GeneratedLayout {
  Scene scene;
  ValidationSpec validation;
};

/// Throw InputError for a bad parameter combination, ScenarioError when the parameters can never fit.
GeneratedLayout generateSorting(const FamilyInput& in);
GeneratedLayout generateWall(const FamilyInput& in);
GeneratedLayout generateShelfWall(const FamilyInput& in);
GeneratedLayout generateStocking(const FamilyInput& in);
GeneratedLayout generateLab(const FamilyInput& in);

/// The generator record and the scene name ("sorting-r4-o8-s3") for a family's parameters.
SceneGenerator generatorRecord(const FamilyInput& in);
std::string sceneName(const FamilyInput& in, const std::string& short_params);

}  // namespace dash
