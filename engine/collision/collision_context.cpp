#include "engine/collision/collision_context.h"

namespace dash {

CollisionContext::CollisionContext(const CollisionWorld& world) : world_(&world) {
  scratch_.robots.resize(static_cast<std::size_t>(world.robotCount()));
  for (int r = 0; r < world.robotCount(); ++r) {
    const std::size_t bodies = world.robot(r).bodies.size();
    auto& posed = scratch_.robots[static_cast<std::size_t>(r)];
    posed.frames.assign(bodies, Pose::Identity());
    posed.body_aabb.resize(bodies);
  }
  const auto objects = static_cast<std::size_t>(world.objectCount());
  scratch_.resting.assign(objects, 0);
  scratch_.object_aabb.resize(objects);
  scratch_.object_pose.assign(objects, Pose::Identity());
  scratch_.resting_list.reserve(objects);
  auto& c = scratch_.candidates;
  c.obstacles.reserve(world.obstacles().size());
  c.held_obstacles.reserve(world.obstacles().size());
  c.objects.reserve(objects);
  scratch_.robots_in_query.reserve(static_cast<std::size_t>(world.robotCount()));
}

}  // namespace dash
