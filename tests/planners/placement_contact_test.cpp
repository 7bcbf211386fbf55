// No scraping at placement (issue 36, item 9): a held item comes down onto its support (and lifts off
// it) without pressing into it. Stocking 3 layers / 6 objects, seed 1: before the approaches and
// retreats were straight TCP lines (cartesian_path.h), Lazy-DaSH's plan put new_1 0.87 mm into
// shelf_c0_l0_d2_pedestal while sliding it into the deepest slot of its cubby, and the validator
// accepted it (1 mm of tolerance at a held object's lowest face, now 0.1 mm).
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/collision/distance_queries.h"
#include "engine/plan/plan_validator.h"
#include "engine/plan/validation_timeline.h"
#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"

namespace dash {
namespace {

/// Near a grasp or a release: the smallest signed distance (m) between a held object's exact box and
/// any obstacle or resting object, sampled every millisecond over the first and last `window` seconds
/// of every stretch the object is held; and at each release of an object that then rests, the largest
/// distance from it to the nearest thing (it must sit on its support).
struct HeldContact {
  double deepest = std::numeric_limits<double>::infinity();
  double farthest_release = 0.0;
};

double nearest(const CollisionWorld& world, CollisionContext& context, int j, const Pose& X_WO,
               const ObjectLayout& layout) {
  const ObjectGeometry& g = world.object(j);
  double d = std::numeric_limits<double>::infinity();
  for (const ObstacleGeometry& o : world.obstacles())
    d = std::min(d, signedDistance(context, *g.shape, X_WO, *o.shape, o.X_WO));
  for (int k = 0; k < layout.size(); ++k)
    if (k != j && layout.isPresent(k))
      d = std::min(
          d, signedDistance(context, *g.shape, X_WO, *world.object(k).shape, layout.X_WO[static_cast<std::size_t>(k)]));
  return d;
}

HeldContact heldContact(const Scene& scene, const Plan& plan, double window = 1.5) {
  const CollisionWorld world(scene, CollisionWorldOptions{.clearance = 0.0, .cover = false});
  CollisionContext context(world);
  const validation::PlanMotion motion(scene, plan);
  std::vector<ValidationProblem> problems;
  const validation::Timeline timeline = validation::replayEvents(plan, motion, ValidationOptions{}, problems);
  HeldContact out;
  const auto& epochs = timeline.epochs;
  for (std::size_t e = 0; e < epochs.size(); ++e) {
    const double t0 = epochs[e].t;
    const double t1 = e + 1 < epochs.size() ? epochs[e + 1].t : plan.makespan;
    for (int j = 0; j < world.objectCount(); ++j) {
      const validation::ObjectState& state = epochs[e].objects[static_cast<std::size_t>(j)];
      if (!state.held()) {
        // Just released (it was held in the epoch before): it rests where it was let go.
        if (e > 0 && epochs[e - 1].objects[static_cast<std::size_t>(j)].held())
          out.farthest_release =
              std::max(out.farthest_release, nearest(world, context, j, state.X_WO, epochs[e].layout));
        continue;
      }
      for (double t = t0; t <= t1; t += 1e-3) {
        if (t > t0 + window && t < t1 - window) t = t1 - window;
        const Pose X_WO = motion.tcp(state.holders[0].robot, t) * state.holders[0].X_TO;
        out.deepest = std::min(out.deepest, nearest(world, context, j, X_WO, epochs[e].layout));
      }
    }
  }
  return out;
}

void expectNoScraping(const char* planner) {
  const Scene scene = generateScenario("stocking", {{"layers", "3"}, {"objects", "6"}}, 1, RobotLibrary::loadDefault());
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = 240;
  const PlanResult result = makePlanner(planner)->solve(scene, settings, Deadline(settings.time_limit), nullptr);
  ASSERT_EQ(result.outcome, PlanOutcome::kSolved) << result.message;
  ASSERT_TRUE(result.plan.has_value());
  const ValidationReport report = validatePlan(scene, *result.plan);
  EXPECT_TRUE(report.valid()) << report.summary();
  const HeldContact contact = heldContact(scene, *result.plan);
  EXPECT_GT(contact.deepest, -kHeldBottomTolerance)
      << "a held object goes " << -contact.deepest * 1e3 << " mm into something";
  EXPECT_LT(contact.farthest_release, kHeldBottomTolerance)
      << "an object let go " << contact.farthest_release * 1e3 << " mm above its support";
}

TEST(PlacementContact, LazyDashOnStockingThreeLayersNeverPressesAHeldItemIntoItsSupport) {
  expectNoScraping("lazy-dash");
}

}  // namespace
}  // namespace dash
