#pragma once
// Scenes of every scenario family and random robot states in them, for the tests of the covers
// (engine/collision/link_cover.h, cover_check.h).
#include <memory>
#include <string>
#include <vector>

#include "engine/collision/collision_queries.h"
#include "engine/core/rng.h"
#include "engine/scenarios/scenario_registry.h"
#include "tests/common/robot_library.h"

namespace dash::test {

struct FamilyScene {
  std::string family;
  std::unique_ptr<Scene> scene;  ///< the world points into it: kept at one address
};

/// One small scene of each family (sorting, wall, shelf-wall, stocking, lab), seed 1.
inline std::vector<FamilyScene> familyScenes() {
  const std::vector<std::pair<std::string, std::vector<std::pair<std::string, std::string>>>> specs = {
      {"sorting", {{"robots", "4"}, {"objects", "8"}}},
      {"wall", {{"robots", "4"}, {"objects", "8"}}},
      {"shelf-wall", {{"robots", "4"}, {"objects", "8"}}},
      {"stocking", {{"layers", "2"}, {"objects", "8"}}},
      {"lab", {}}};
  std::vector<FamilyScene> out;
  for (const auto& [family, overrides] : specs) {
    out.push_back({family, std::make_unique<Scene>(generateScenario(family, overrides, 1, library()))});
  }
  return out;
}

/// A configuration of robot r: uniform over [-pi, pi] (UR) or the limits (gantry) half the time, else
/// near home (Gaussian, 0.6 rad or 0.15 m), clamped into the limits: both far and near contacts.
inline JointVector randomState(const Scene& scene, int r, Rng& rng) {
  const SceneRobot& robot = scene.robots[static_cast<std::size_t>(r)];
  const RobotModel& m = *robot.model;
  const bool ur = m.kinematics == KinematicsKind::kUrDh;
  const bool uniform = rng.uniform01() < 0.5;
  JointVector q(m.dof());
  for (int j = 0; j < m.dof(); ++j) {
    const double lo = ur ? std::max(-M_PI, m.limits.position_min[j]) : m.limits.position_min[j];
    const double hi = ur ? std::min(M_PI, m.limits.position_max[j]) : m.limits.position_max[j];
    const double v = uniform ? rng.uniform(lo, hi) : robot.home[j] + rng.gaussian(0.0, ur ? 0.6 : 0.15);
    q[j] = std::clamp(v, lo, hi);
  }
  return q;
}

/// An object held at a random pose near the TCP (within 6 cm, any orientation), or an empty hand.
inline HeldObject randomHeld(const Scene& scene, Rng& rng, double holding_share) {
  HeldObject held;
  if (scene.objects.empty() || rng.uniform01() >= holding_share) return held;
  held.object = static_cast<int>(rng.integer(0, static_cast<std::int64_t>(scene.objects.size()) - 1));
  const Vec3 axis = Vec3(rng.gaussian(0, 1), rng.gaussian(0, 1), rng.gaussian(0, 1)).normalized();
  held.X_TO = makePose(Vec3(rng.uniform(-0.03, 0.03), rng.uniform(-0.03, 0.03), rng.uniform(0.0, 0.06)),
                       Quat(Eigen::AngleAxisd(rng.uniform(-M_PI, M_PI), axis)));
  held.in_transit = rng.uniform01() < 0.5;
  return held;
}

}  // namespace dash::test
