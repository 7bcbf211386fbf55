// Covers of capsules and boxes (link_cover.h: the containment argument).
#include "engine/collision/link_cover.h"

#include <cmath>

namespace dash {

CoverCapsule capsuleCover(const Vec3& a, const Vec3& b, double radius, double clearance) {
  return {.a = a,
          .b = b,
          .radius_static = radius + clearance + kCoverMargin,
          .radius_robot = radius + 0.5 * clearance + kCoverMargin};
}

CoverCapsule boxCover(const Vec3& center, const Vec3& half, double clearance) {
  int k = 0;
  half.maxCoeff(&k);
  const int i = (k + 1) % 3;
  const int j = (k + 2) % 3;
  Vec3 axis = Vec3::Zero();
  axis[k] = half[k] + clearance;  // the larger growth: the segment serves both radii
  auto across = [&](double g) { return std::hypot(half[i] + g, half[j] + g) + kCoverMargin; };
  return {.a = center - axis,
          .b = center + axis,
          .radius_static = across(clearance),
          .radius_robot = across(0.5 * clearance)};
}

}  // namespace dash
