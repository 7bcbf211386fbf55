#pragma once
// Primitive shapes shared by robot models, scenes and the collision checker.
#include "engine/geometry/pose.h"

namespace dash {

/// Axis-aligned in its own frame, centred on the frame origin; full edge lengths.
struct BoxShape {
  Vec3 size = Vec3::Zero();
};

/// Segment from a to b (in the body frame) swept by a sphere of radius r.
struct CapsuleShape {
  Vec3 a = Vec3::Zero();
  Vec3 b = Vec3::Zero();
  double radius = 0.0;
};

}  // namespace dash
