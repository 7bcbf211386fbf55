#pragma once
// Which pair collided, so planners can turn a failed check into a constraint.
#include <cstdint>
#include <string>

#include "engine/scene/scene.h"

namespace dash {

/// One side of a colliding pair.
struct CollisionElement {
  enum class Kind { kNone, kRobotBody, kHeldObject, kObstacle, kObject };
  Kind kind = Kind::kNone;
  int robot = -1;   ///< kRobotBody, kHeldObject: index into Scene::robots
  int body = -1;    ///< kRobotBody: index into the robot model's bodies
  int index = -1;   ///< kObstacle: Scene::obstacles; kObject (resting), kHeldObject: Scene::objects

  static CollisionElement robotBody(int robot, int body) { return {Kind::kRobotBody, robot, body, -1}; }
  static CollisionElement heldObject(int robot, int object) { return {Kind::kHeldObject, robot, -1, object}; }
  static CollisionElement obstacle(int i) { return {Kind::kObstacle, -1, -1, i}; }
  static CollisionElement object(int j) { return {Kind::kObject, -1, -1, j}; }
  bool operator==(const CollisionElement&) const = default;
};

struct CollisionReport {
  CollisionElement a;  ///< always a robot body or a held object when a robot is involved
  CollisionElement b;
  /// Segment queries: the fraction of the segment (0 = start, 1 = end) where the collision was found.
  double segment_fraction = 0.0;
};

/// E.g. "ur5e_0.forearm vs obstacle table", "object obj_0 (held by ur5e_0) vs object obj_1".
std::string describe(const CollisionElement& element, const Scene& scene);
std::string describe(const CollisionReport& report, const Scene& scene);

/// Work done by one CollisionContext, for the planners' statistics.
struct CollisionCounters {
  std::uint64_t configuration_checks = 0;  ///< configuration (or multi-robot state) checks, incl. segment steps
  std::uint64_t segment_checks = 0;        ///< segment queries
  std::uint64_t narrowphase_calls = 0;     ///< FCL collide calls after the bounding-box tests
  std::uint64_t distance_queries = 0;
  std::uint64_t cover_cleared = 0;  ///< segment steps the covers cleared, not counted as configuration checks
};

}  // namespace dash
