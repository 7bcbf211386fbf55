// The index of conflict resolution's scheduled pieces (engine/conflict/segment_boxes.h): a piece's box
// contains the robot's parts over the piece, so two pieces whose boxes are apart never collide; and a
// box is computed once per segment while that segment stays the same.
#include <gtest/gtest.h>

#include "engine/collision/segment_queries.h"
#include "engine/conflict/segment_boxes.h"
#include "tests/collision/cover_test_util.h"
#include "tests/conflict/two_arms.h"

namespace dash {
namespace {

/// A timeline of robot r through three random configurations (2 s apart), holding a random object
/// from a random instant of the first segment to one of the second, or for good.
RobotTimeline randomTimeline(const Scene& scene, int r, Rng& rng) {
  RobotTimeline t(r, test::randomState(scene, r, rng));
  t.append(2.0, test::randomState(scene, r, rng));
  t.append(4.0, test::randomState(scene, r, rng));
  const HeldObject held = test::randomHeld(scene, rng, 0.6);
  if (held.holding()) {
    t.grasp(rng.uniform(0.0, 2.0), held);
    if (rng.uniform01() < 0.5) t.release(rng.uniform(2.0, 4.0));
  }
  return t;
}

// Sorting, wall and shelf-wall scenes (4 arms) and the lab's gantries: random timelines of two robots,
// random pieces of them. Wherever the index calls the pieces apart, the exact robot-robot check over
// the piece (both robots moving together, what each holds at the piece's middle) finds them free. A box
// that missed the motion between the ends or the held object would fail here: the test also requires
// pieces whose ends are apart but whose motions collide.
TEST(SegmentBoxes, PiecesWhoseBoxesAreApartNeverCollide) {
  Rng rng(38);
  int apart = 0, colliding = 0, ends_apart_but_colliding = 0;
  for (const test::FamilyScene& f : test::familyScenes()) {
    if (f.scene->robots.size() < 2) continue;
    CollisionWorld world(*f.scene, {.clearance = kDefaultPlanningClearance});
    CollisionContext context(world);
    SegmentBoxes boxes(world, context);
    const ObjectLayout none = ObjectLayout::empty(*f.scene);
    const int n = static_cast<int>(f.scene->robots.size());
    for (int trial = 0; trial < 150; ++trial) {
      const int a = static_cast<int>(rng.integer(0, n - 1));
      const int b = (a + 1 + static_cast<int>(rng.integer(0, n - 2))) % n;
      const RobotTimeline ta = randomTimeline(*f.scene, a, rng), tb = randomTimeline(*f.scene, b, rng);
      for (int piece = 0; piece < 6; ++piece) {
        const double s = 2.0 * static_cast<double>(rng.integer(0, 2));  // a segment, or the standing after
        const double u = s + rng.uniform(0.0, 1.0), v = s + rng.uniform(1.0, 2.0), mid = 0.5 * (u + v);
        const auto box_a = boxes.pieceBox(ta, u, v), box_b = boxes.pieceBox(tb, u, v);
        ASSERT_TRUE(box_a && box_b) << "a piece inside one segment has a box";
        const RobotMotion motions[2] = {{{a, ta.at(u), ta.heldAt(mid)}, ta.at(v)}, {{b, tb.at(u), tb.heldAt(mid)}, tb.at(v)}};
        const bool collides =
            motionsInCollision(world, context, motions, none, nullptr, {.scope = CheckScope::kRobotsOnly, .resolution = 0.002});
        colliding += collides;
        if (box_a->intersects(*box_b)) continue;
        ++apart;
        EXPECT_FALSE(collides) << f.family << " robots " << a << ", " << b << " over [" << u << ", " << v << "]";
      }
      // The segments' ends alone (no motion in between) apart, the motion colliding: what the boxes must cover.
      const RobotMotion ends[2] = {{{a, ta.at(0.0), ta.heldAt(0.0)}, ta.at(0.0)}, {{b, tb.at(0.0), tb.heldAt(0.0)}, tb.at(0.0)}};
      const RobotMotion moves[2] = {{{a, ta.at(0.0), ta.heldAt(1.0)}, ta.at(2.0)}, {{b, tb.at(0.0), tb.heldAt(1.0)}, tb.at(2.0)}};
      if (!motionsInCollision(world, context, ends, none, nullptr, {.scope = CheckScope::kRobotsOnly}) &&
          motionsInCollision(world, context, moves, none, nullptr, {.scope = CheckScope::kRobotsOnly}))
        ++ends_apart_but_colliding;
    }
  }
  EXPECT_GT(apart, 100) << colliding << " colliding, " << ends_apart_but_colliding << " with ends apart";
  EXPECT_GT(colliding, 50);
  EXPECT_GT(ends_apart_but_colliding, 10);
}

// A segment's box is computed once while the segment stays the same, again when it changes (a rewound
// timeline that goes elsewhere, or a grasp added along it).
TEST(SegmentBoxes, ASegmentsBoxIsComputedOnceWhileItStaysTheSame) {
  testing::TwoArms arms;
  SegmentBoxes boxes(arms.world, arms.context);
  RobotTimeline t(0, arms.scene.robots[0].home);
  JointVector q = arms.scene.robots[0].home;
  q[0] += 0.5;
  const RobotTimeline::Mark mark = t.mark();
  t.append(2.0, q);
  const auto first = boxes.pieceBox(t, 0.5, 1.0);
  ASSERT_TRUE(first);
  EXPECT_EQ(boxes.computed(), 1u);
  EXPECT_TRUE(boxes.pieceBox(t, 1.0, 2.0));
  EXPECT_EQ(boxes.computed(), 1u);
  EXPECT_FALSE(boxes.pieceBox(t, 1.0, 3.0)) << "across a point: no box";
  t.rewind(mark);
  q[0] -= 1.0;
  t.append(2.0, q);
  const auto moved = boxes.pieceBox(t, 0.5, 1.0);
  EXPECT_EQ(boxes.computed(), 2u);
  EXPECT_FALSE(moved->isApprox(*first));
  t.grasp(1.5, {0, Pose::Identity(), false});
  EXPECT_TRUE(boxes.pieceBox(t, 0.5, 1.0));
  EXPECT_EQ(boxes.computed(), 3u);
}

}  // namespace
}  // namespace dash
