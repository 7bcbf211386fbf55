#include "engine/collision/region_queries.h"

#include <vector>

#include "engine/collision/collision_internal.h"
#include "engine/collision/segment_queries.h"

namespace dash {

namespace {

bool meetsAny(const Aabb& box, std::span<const Aabb> regions) {
  for (const Aabb& region : regions)
    if (box.intersects(region)) return true;
  return false;
}

}  // namespace

bool robotEntersRegions(const CollisionWorld& world, CollisionContext& context, const RobotState& state,
                        std::span<const Aabb> regions) {
  if (regions.empty()) return false;
  detail::poseRobot(world, context, state.robot, state.q, state.held);
  const auto& posed = context.scratch().robots[static_cast<std::size_t>(state.robot)];
  if (!meetsAny(detail::postureBox(posed), regions)) return false;
  for (const Aabb& body : posed.body_aabb)
    if (meetsAny(body, regions)) return true;
  return posed.held_object >= 0 && meetsAny(posed.held_aabb, regions);
}

bool segmentEntersRegions(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                          const JointVector& q_end, std::span<const Aabb> regions) {
  if (regions.empty()) return false;
  const int n = segmentSteps(world, start.robot, start.q, q_end, start.held);
  std::vector<Aabb> parts;
  RobotState from = start;
  for (int i = 1; i <= n; ++i) {
    const JointVector to = start.q + (static_cast<double>(i) / n) * (q_end - start.q);
    parts.clear();
    sweptPartBoxes(world, context, from, to, parts);
    for (const Aabb& part : parts)
      if (meetsAny(part, regions)) return true;
    from.q = to;
  }
  return false;
}

}  // namespace dash
