#pragma once
// Where the scene's objects rest at one moment of a plan: a pose per object plus a mask of the objects
// that are present (considered). A held object is not part of the layout's resting set while held;
// queries skip it automatically. Plain value type: copy freely, or reuse one and edit it in place.
#include <cstdint>
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/scene/scene.h"

namespace dash {

struct ObjectLayout {
  std::vector<Pose> X_WO;            ///< one per Scene::objects entry
  std::vector<std::uint8_t> present;  ///< 1 = rests at X_WO[j] and is checked; 0 = ignored

  /// Every object at its start pose.
  static ObjectLayout atStart(const Scene& scene);
  /// Every object at its goal pose, or at its start pose if it has no goal.
  static ObjectLayout atGoal(const Scene& scene);
  /// Every object at its start pose, none present (queries see no objects).
  static ObjectLayout empty(const Scene& scene);

  int size() const { return static_cast<int>(X_WO.size()); }
  bool isPresent(int object) const { return present[static_cast<std::size_t>(object)] != 0; }
  void place(int object, const Pose& X) {
    X_WO[static_cast<std::size_t>(object)] = X;
    present[static_cast<std::size_t>(object)] = 1;
  }
  void remove(int object) { present[static_cast<std::size_t>(object)] = 0; }
};

}  // namespace dash
