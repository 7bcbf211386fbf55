#include "engine/scene/scene.h"

#include <algorithm>

namespace dash {

namespace {

template <class Items>
int indexById(const Items& items, const std::string& id) {
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (items[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

}  // namespace

bool SceneRobot::hasCapability(const std::string& capability) const {
  return std::find(capabilities.begin(), capabilities.end(), capability) != capabilities.end();
}

int Scene::robotIndex(const std::string& id) const { return indexById(robots, id); }
int Scene::objectIndex(const std::string& id) const { return indexById(objects, id); }
int Scene::obstacleIndex(const std::string& id) const { return indexById(obstacles, id); }

}  // namespace dash
