// The covers of engine/collision/link_cover.h: they contain the exact shapes, and over a million random
// configurations in scenes of every family they never clear one that the exact model (FCL, the fast
// path off) finds in collision.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "engine/collision/cover_check.h"
#include "tests/collision/cover_test_util.h"

namespace dash {
namespace {

/// Whether p lies in the capsule a-b of radius r (with 1e-12 m of rounding).
bool inCapsule(const Vec3& p, const Vec3& a, const Vec3& b, double r) {
  const Vec3 d = b - a;
  const double t = d.squaredNorm() > 0.0 ? std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm() <= r + 1e-12;
}

/// Every corner of the box (centre, half extents + growth) lies in the cover at `radius`: the box is
/// the convex hull of its corners and the capsule is convex.
void expectBoxInside(const Vec3& center, const Vec3& half, double growth, const CoverCapsule& c, double radius,
                     const std::string& what) {
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 p = center;
    for (int k = 0; k < 3; ++k) p[k] += ((corner >> k) & 1 ? 1.0 : -1.0) * (half[k] + growth);
    EXPECT_TRUE(inCapsule(p, c.a, c.b, radius)) << what << " corner " << corner << " growth " << growth;
  }
}

TEST(LinkCover, EveryBodyAndObjectGrownByTheClearanceLiesInsideItsCover) {
  for (const double clearance : {0.0, 0.002, 0.01, 0.1}) {
    for (const auto& name : test::library()->names()) {
      const RobotModel& m = test::library()->get(name);
      for (const CollisionBody& body : m.bodies) {
        if (body.kind == CollisionBody::Kind::kCapsule) {
          const CoverCapsule c = capsuleCover(body.capsule.a, body.capsule.b, body.capsule.radius, clearance);
          EXPECT_EQ(c.a, body.capsule.a);
          EXPECT_EQ(c.b, body.capsule.b);
          EXPECT_GE(c.radius_static, body.capsule.radius + clearance + kCoverMargin - 1e-15) << body.name;
          EXPECT_GE(c.radius_robot, body.capsule.radius + 0.5 * clearance + kCoverMargin - 1e-15) << body.name;
        } else {
          const CoverCapsule c = boxCover(body.box_center, body.box_half_extents, clearance);
          expectBoxInside(body.box_center, body.box_half_extents, clearance, c, c.radius_static,
                          name + "." + body.name);
          expectBoxInside(body.box_center, body.box_half_extents, 0.5 * clearance, c, c.radius_robot,
                          name + "." + body.name);
        }
      }
    }
    for (const Vec3& half :
         {Vec3(0.02, 0.02, 0.02), Vec3(0.04, 0.04, 0.06), Vec3(0.1, 0.01, 0.03), Vec3(0.005, 0.2, 0.2)}) {
      const CoverCapsule c = boxCover(Vec3::Zero(), half, clearance);
      expectBoxInside(Vec3::Zero(), half, clearance, c, c.radius_static, "object");
      expectBoxInside(Vec3::Zero(), half, 0.5 * clearance, c, c.radius_robot, "object");
    }
  }
}

struct Tally {
  long configurations = 0, colliding = 0, cleared = 0, wrongly_cleared = 0;
};

/// kBatchLanes random configurations of one robot (holding something or not) among the others, parked at
/// random configurations (some holding objects), and the scene's resting objects: the cover's verdict
/// per lane against the exact check's.
void checkOneBatch(const CollisionWorld& world, CollisionContext& context, Rng& rng, Tally& tally) {
  const Scene& scene = world.scene();
  const int r = static_cast<int>(rng.integer(0, world.robotCount() - 1));
  RobotState state{.robot = r, .held = test::randomHeld(scene, rng, 0.3)};
  std::vector<RobotState> parked;
  for (int p = 0; p < world.robotCount(); ++p) {
    if (p == r) continue;
    HeldObject held = test::randomHeld(scene, rng, 0.3);
    if (held.object == state.held.object) held = {};
    for (const RobotState& other : parked)
      if (held.object == other.held.object) held = {};
    parked.push_back({.robot = p, .q = test::randomState(scene, p, rng), .held = held});
  }
  const ObjectLayout layout = ObjectLayout::atStart(scene);
  std::vector<JointVector> qs(kBatchLanes);
  JointBatch qb;
  for (int l = 0; l < kBatchLanes; ++l) {
    qs[static_cast<std::size_t>(l)] = test::randomState(scene, r, rng);
    qb.set(l, qs[static_cast<std::size_t>(l)]);
  }
  // The cover, as the segment queries use it.
  std::vector<RobotState> all = parked;
  all.push_back({.robot = r, .q = qs[0], .held = state.held});
  detail::prepareResting(world, context, layout, all);
  std::vector<int> posed;
  detail::poseParked(world, context, parked, posed);
  std::vector<detail::RobotCoverBatch> others(posed.size());
  for (std::size_t i = 0; i < posed.size(); ++i) detail::coverFromPosed(world, context, posed[i], others[i]);
  detail::CandidateView view = detail::fullCandidates(world, context, r, CheckScope::kAll);
  view.robots = posed;
  FrameBatch frames;
  batchFrames(*world.robot(r).model, world.robot(r).robot->X_WB, qb, frames);
  detail::RobotCoverBatch mine;
  detail::coverFromFrames(world, r, frames, state.held, mine);
  alignas(64) double clear[kBatchLanes];
  std::fill_n(clear, kBatchLanes, 1.0);
  detail::clearAgainstCandidates(world, context, mine, view, others, clear);
  // The exact model: FCL on every pair the bounding boxes leave.
  setCoverFastPath(false);
  for (int l = 0; l < kBatchLanes; ++l) {
    state.q = qs[static_cast<std::size_t>(l)];
    const bool collides = robotsAmongParked(world, context, std::span<const RobotState>(&state, 1), parked, layout);
    ++tally.configurations;
    tally.colliding += collides ? 1 : 0;
    tally.cleared += clear[l] != 0.0 ? 1 : 0;
    tally.wrongly_cleared += (collides && clear[l] != 0.0) ? 1 : 0;
  }
  setCoverFastPath(true);
}

TEST(LinkCover, NeverClearsAConfigurationTheExactModelFindsInCollisionOverAMillionInEveryFamily) {
  constexpr long kConfigurations = 1'000'000;
  const auto scenes = test::familyScenes();
  const long per_scene = kConfigurations / static_cast<long>(scenes.size() * 2) + kBatchLanes;
  Tally total;
  for (const auto& fs : scenes) {
    for (const double clearance : {0.0, kDefaultPlanningClearance}) {
      const CollisionWorld world(*fs.scene, {.clearance = clearance});
      CollisionContext context(world);
      Rng rng(Rng::derive(38, static_cast<std::uint64_t>(total.configurations)));
      Tally tally;
      while (tally.configurations < per_scene) checkOneBatch(world, context, rng, tally);
      std::printf("%-10s clearance %.3f: %ld configurations, %ld in collision, %ld cleared by the cover\n",
                  fs.family.c_str(), clearance, tally.configurations, tally.colliding, tally.cleared);
      EXPECT_EQ(tally.wrongly_cleared, 0) << fs.family << " clearance " << clearance;
      // Meaningful: collisions happen, and the cover clears a good share of the free configurations.
      EXPECT_GT(tally.colliding, per_scene / 50) << fs.family;
      EXPECT_GT(tally.cleared, (tally.configurations - tally.colliding) / 4) << fs.family;
      total.configurations += tally.configurations;
      total.wrongly_cleared += tally.wrongly_cleared;
    }
  }
  EXPECT_GE(total.configurations, kConfigurations);
  EXPECT_EQ(total.wrongly_cleared, 0);
}

}  // namespace
}  // namespace dash
