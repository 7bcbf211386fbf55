#include <gtest/gtest.h>

#include <unordered_set>

#include "engine/core/deadline.h"
#include "engine/core/ids.h"
#include "engine/core/rng.h"
#include "engine/geometry/pose.h"

namespace dash {
namespace {

struct FooTag {};
using FooId = StrongId<FooTag>;

TEST(StrongId, DefaultIsInvalidAndHashes) {
  FooId none;
  EXPECT_FALSE(none.valid());
  FooId a(3), b(3), c(4);
  EXPECT_EQ(a, b);
  EXPECT_LT(a, c);
  std::unordered_set<FooId> set{a, b, c};
  EXPECT_EQ(set.size(), 2u);
}

TEST(Rng, SameSeedSameStream) {
  Rng r1(42), r2(42), r3(43);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(r1.uniform01(), r2.uniform01());
  EXPECT_NE(Rng(42).uniform01(), r3.uniform01());
  EXPECT_EQ(Rng::derive(7, 1), Rng::derive(7, 1));
  EXPECT_NE(Rng::derive(7, 1), Rng::derive(7, 2));
}

TEST(Deadline, StopFlagExpires) {
  std::atomic<bool> stop{false};
  Deadline d(1e12, &stop);
  EXPECT_FALSE(d.expired());
  stop = true;
  EXPECT_TRUE(d.expired());
  EXPECT_TRUE(Deadline(-1.0).expired());
}

TEST(Pose, QuaternionRoundTrip) {
  const Pose X = makePose(Vec3(1, 2, 3), Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())));
  const auto q = quatXYZW(X);
  const Pose Y = makePose(X.translation(), quatFromXYZW(q));
  EXPECT_LT(rotationDistance(X, Y), 1e-12);
  EXPECT_LT(translationDistance(X, Y), 1e-12);
}

}  // namespace
}  // namespace dash
