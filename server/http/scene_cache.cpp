#include "server/http/scene_cache.h"

#include "engine/scenarios/scenario_registry.h"
#include "engine/scene/scene_json.h"

namespace dash::http {

SceneCache::SceneCache(std::shared_ptr<const RobotLibrary> robots, std::size_t capacity)
    : robots_(std::move(robots)), capacity_(capacity) {}

std::string SceneCache::sceneJson(const std::string& family, const std::vector<std::pair<std::string, int>>& params,
                                  std::uint64_t seed) {
  const ScenarioFamily& f = scenarioFamily(family);
  // The family's order, as the batch runner's RunSpec holds them (ScenarioParams is positional).
  std::vector<std::pair<std::string, std::string>> overrides;
  for (const ParamSpec& spec : f.params) {
    for (const auto& [name, value] : params) {
      if (name == spec.name) overrides.emplace_back(name, std::to_string(value));
    }
  }
  const ScenarioParams resolved = resolveParams(family, f.params, overrides);
  std::string key = family + "/" + std::to_string(seed);
  for (const auto& [name, value] : resolved.values()) key += "/" + name + "=" + std::to_string(value);
  {
    std::lock_guard lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end(); ++it) {
      if (it->first == key) {
        entries_.splice(entries_.begin(), entries_, it);
        return entries_.front().second;
      }
    }
  }
  // Generated outside the lock: another request may generate the same scene meanwhile; both agree.
  std::string json = sceneToJson(generateScenario(family, resolved, seed, robots_));
  std::lock_guard lock(mutex_);
  entries_.emplace_front(key, json);
  while (entries_.size() > capacity_) entries_.pop_back();
  return json;
}

}  // namespace dash::http
