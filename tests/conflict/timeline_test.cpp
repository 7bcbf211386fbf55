// What a robot's timeline says it holds: during a hold interval, and from its last point on (the
// scheduler replans from there, so a robot still holding an object must be planned with it).
#include <gtest/gtest.h>

#include "engine/conflict/timeline.h"

namespace dash {
namespace {

JointVector zeros() { return JointVector::Zero(6); }

TEST(RobotTimeline, HoldsAnObjectUntilItIsReleased) {
  RobotTimeline tl(0, zeros());
  tl.append(1.0, zeros());
  tl.grasp(1.0, HeldObject{3, Pose::Identity()});
  tl.append(2.0, zeros());
  EXPECT_EQ(tl.heldAt(0.5).object, -1);
  EXPECT_EQ(tl.heldAt(1.5).object, 3);
  EXPECT_EQ(tl.heldAtEnd().object, 3);  // never released: still held after the last point
  tl.release(2.0);
  EXPECT_EQ(tl.heldAt(1.5).object, 3);
  EXPECT_EQ(tl.heldAt(2.5).object, -1);
  EXPECT_EQ(tl.heldAtEnd().object, -1);
}

TEST(RobotTimeline, EmptyHandedWithNoGrasp) {
  RobotTimeline tl(1, zeros());
  EXPECT_EQ(tl.heldAtEnd().object, -1);
}

}  // namespace
}  // namespace dash
