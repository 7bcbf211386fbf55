#pragma once
// The scene a run planned, regenerated from its family, parameters and seed with the scenario
// registry (exactly as the run's own process generated it), as dashbench.scene/1 JSON for the 3D
// view. Generation validates the layout and can take a moment, so the last few scenes are kept.
#include <cstdint>
#include <list>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "engine/robots/robot_model.h"

namespace dash::http {

class SceneCache {
 public:
  explicit SceneCache(std::shared_ptr<const RobotLibrary> robots, std::size_t capacity = 8);

  /// Parameters in any order; missing ones take the family's default. Throws InputError (unknown
  /// family, bad parameters) or ScenarioError (no valid layout).
  std::string sceneJson(const std::string& family, const std::vector<std::pair<std::string, int>>& params,
                        std::uint64_t seed);
  const std::shared_ptr<const RobotLibrary>& robots() const { return robots_; }

 private:
  std::shared_ptr<const RobotLibrary> robots_;
  std::size_t capacity_;
  std::mutex mutex_;
  std::list<std::pair<std::string, std::string>> entries_;  ///< key -> JSON, most recent first
};

}  // namespace dash::http
