#include "engine/task/task_space.h"

#include "engine/core/check.h"

namespace dash {

namespace {
constexpr double kSameLocationMetres = 1e-3;
constexpr double kSameLocationRadians = 1e-2;

/// Index of the surface whose plane the pose's object bottom lies on, -1 if none.
int supportingSurface(const Scene& scene, const SceneObject& object, const Pose& X_WO) {
  const double bottom = X_WO.translation().z() - 0.5 * object.shape.size.z();
  int best = -1;
  double best_gap = 2e-3;
  for (int s = 0; s < static_cast<int>(scene.surfaces.size()); ++s) {
    const double gap = std::abs(scene.surfaces[s].z - bottom);
    if (gap < best_gap) {
      best_gap = gap;
      best = s;
    }
  }
  return best;
}
}  // namespace

TaskSpace::TaskSpace(const Scene& scene) : scene_(&scene) {
  locations_.resize(scene.objects.size());
  for (std::size_t j = 0; j < scene.objects.size(); ++j) {
    const SceneObject& object = scene.objects[j];
    auto& locs = locations_[j];
    const bool same = object.X_WO_goal &&
                      translationDistance(object.X_WO_start, *object.X_WO_goal) < kSameLocationMetres &&
                      rotationDistance(object.X_WO_start, *object.X_WO_goal) < kSameLocationRadians;
    const int start_surface = supportingSurface(scene, object, object.X_WO_start);
    if (same || !object.X_WO_goal) {
      locs.push_back({same ? ObjectLocation::Kind::kStartAndGoal : ObjectLocation::Kind::kStart,
                      object.X_WO_start, false, start_surface});
    } else {
      locs.push_back({ObjectLocation::Kind::kStart, object.X_WO_start, false, start_surface});
      locs.push_back({ObjectLocation::Kind::kGoal, *object.X_WO_goal, false,
                      supportingSurface(scene, object, *object.X_WO_goal)});
    }
  }
}

int TaskSpace::startLocation(int object) const {
  const auto& locs = locations_[object];
  for (int l = 0; l < static_cast<int>(locs.size()); ++l)
    if (locs[l].isStart()) return l;
  DASH_DEMAND_MSG(false, "every object has a start location");
}

int TaskSpace::goalLocation(int object) const {
  const auto& locs = locations_[object];
  for (int l = 0; l < static_cast<int>(locs.size()); ++l)
    if (locs[l].isGoal()) return l;
  return -1;
}

int TaskSpace::addExtraLocation(int object, const Pose& X_WO, int surface) {
  locations_[object].push_back({ObjectLocation::Kind::kExtra, X_WO, true, surface});
  return static_cast<int>(locations_[object].size()) - 1;
}

void TaskSpace::resample(int object, int index, const Pose& X_WO, int surface) {
  ObjectLocation& loc = locations_[object][index];
  DASH_DEMAND(loc.resampleable);
  loc.X_WO = X_WO;
  if (surface >= 0) loc.surface = surface;
}

int TaskSpace::extraLocationCount(int object) const {
  int n = 0;
  for (const auto& l : locations_[object]) n += l.kind == ObjectLocation::Kind::kExtra ? 1 : 0;
  return n;
}

std::string TaskSpace::locationLabel(int object, int index) const {
  const ObjectLocation& loc = locations_[object][index];
  const std::string& id = scene_->objects[object].id;
  switch (loc.kind) {
    case ObjectLocation::Kind::kStart: return id + "@start";
    case ObjectLocation::Kind::kGoal: return id + "@goal";
    case ObjectLocation::Kind::kStartAndGoal: return id + "@start=goal";
    case ObjectLocation::Kind::kExtra: return id + "@extra" + std::to_string(index);
  }
  return id;
}

}  // namespace dash
