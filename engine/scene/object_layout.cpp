#include "engine/scene/object_layout.h"

namespace dash {

ObjectLayout ObjectLayout::atStart(const Scene& scene) {
  ObjectLayout layout;
  layout.X_WO.reserve(scene.objects.size());
  for (const auto& o : scene.objects) layout.X_WO.push_back(o.X_WO_start);
  layout.present.assign(scene.objects.size(), 1);
  return layout;
}

ObjectLayout ObjectLayout::atGoal(const Scene& scene) {
  ObjectLayout layout;
  layout.X_WO.reserve(scene.objects.size());
  for (const auto& o : scene.objects) layout.X_WO.push_back(o.X_WO_goal ? *o.X_WO_goal : o.X_WO_start);
  layout.present.assign(scene.objects.size(), 1);
  return layout;
}

ObjectLayout ObjectLayout::empty(const Scene& scene) {
  ObjectLayout layout = atStart(scene);
  layout.present.assign(scene.objects.size(), 0);
  return layout;
}

}  // namespace dash
