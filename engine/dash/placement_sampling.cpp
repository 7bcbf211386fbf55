#include "engine/dash/placement_sampling.h"

#include <algorithm>
#include <cmath>

#include "engine/collision/collision_queries.h"
#include "engine/placement/placement_region.h"

namespace dash {

namespace {

constexpr int kPlacementAttempts = 400;

/// Diagonal of a box's footprint: no two footprints overlap when centres are this far apart (average).
double footprint(const BoxShape& box) { return std::hypot(box.size.x(), box.size.y()); }

bool graspable(GeometricReachability& reach, int robot, int object, const Pose& X_WO) {
  return reach.canGrasp(robot, object, X_WO, GraspClass::kTop) || reach.canGrasp(robot, object, X_WO, GraspClass::kSide);
}

}  // namespace

void presamplePlacements(TaskSpace& space, GeometricReachability& reach, TransitionSampler& sampler, Rng& rng,
                         const PlacementSamplingParams& params) {
  const Scene& scene = space.scene();
  if (params.per_robot <= 0 || scene.surfaces.empty()) return;
  std::vector<PlacementRegion> regions;
  for (const SceneSurface& s : scene.surfaces) regions.emplace_back(s);
  const ObjectLayout none = ObjectLayout::empty(scene);
  // One pool per object size: the objects that share it (movable ones only).
  std::vector<std::vector<int>> sizes;
  for (int o = 0; o < space.objectCount(); ++o) {
    if (space.isFixed(o)) continue;
    auto same = std::find_if(sizes.begin(), sizes.end(), [&](const std::vector<int>& g) {
      return scene.objects[g.front()].shape.size == scene.objects[o].shape.size;
    });
    if (same == sizes.end()) {
      sizes.push_back({o});
    } else {
      same->push_back(o);
    }
  }
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    if (!scene.robots[r].hasCapability("grasp")) continue;
    for (const std::vector<int>& group : sizes) {
      const int o = group.front();  // stands for every object of its size
      const BoxShape& box = scene.objects[o].shape;
      for (int added = 0, attempt = 0; added < params.per_robot && attempt < kPlacementAttempts; ++attempt) {
        const int s = static_cast<int>(rng.integer(0, static_cast<std::int64_t>(regions.size()) - 1));
        const auto pose = regions[s].sampleNear(box, scene.robots[r].X_WB.translation(), params.radius, rng, 4);
        if (!pose) continue;
        bool clear = true;
        for (int j = 0; j < space.objectCount() && clear; ++j) {
          // Far enough from every known location that the two footprints cannot overlap.
          const double spacing = std::max(params.spacing, 0.5 * (footprint(box) + footprint(scene.objects[j].shape)));
          for (const ObjectLocation& l : space.locations(j))
            clear = clear && (l.X_WO.translation() - pose->translation()).norm() >= spacing;
        }
        if (!clear || objectInCollision(sampler.world(), sampler.context(), o, *pose, none)) continue;
        if (!graspable(reach, r, o, *pose)) continue;
        for (int j : group) space.addExtraLocation(j, *pose, s);
        ++added;
      }
    }
  }
}

}  // namespace dash
