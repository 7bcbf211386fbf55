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
  if (params.per_object <= 0 || scene.surfaces.empty()) return;
  std::vector<PlacementRegion> regions;
  for (const SceneSurface& s : scene.surfaces) regions.emplace_back(s);
  const ObjectLayout none = ObjectLayout::empty(scene);
  struct Sampled {
    int object;
    Pose X_WO;
    int surface;
  };
  std::vector<Sampled> sampled;
  std::vector<int> short_of;  // objects that found too little room
  for (int o = 0; o < space.objectCount(); ++o) {
    if (space.isFixed(o)) continue;
    std::vector<int> robots;
    for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
      if (!scene.robots[r].hasCapability("grasp")) continue;
      bool takes = graspable(reach, r, o, space.location(o, space.startLocation(o)).X_WO);
      if (space.goalLocation(o) >= 0) takes = takes || graspable(reach, r, o, space.location(o, space.goalLocation(o)).X_WO);
      if (takes) robots.push_back(r);
    }
    if (robots.empty()) continue;
    const BoxShape& box = scene.objects[o].shape;
    int added = 0;
    for (int attempt = 0; added < params.per_object && attempt < kPlacementAttempts; ++attempt) {
      const int r = robots[static_cast<std::size_t>(rng.integer(0, static_cast<std::int64_t>(robots.size()) - 1))];
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
      space.addExtraLocation(o, *pose, s);
      sampled.push_back({o, *pose, s});
      ++added;
    }
    if (added < params.per_object) short_of.push_back(o);
  }
  // No room left near the robots for these: they share the placements of objects of their size.
  for (int o : short_of)
    for (const Sampled& p : sampled) {
      if (space.extraLocationCount(o) >= params.per_object) break;
      if (p.object != o && scene.objects[p.object].shape.size == scene.objects[o].shape.size)
        space.addExtraLocation(o, p.X_WO, p.surface);
    }
}

}  // namespace dash
