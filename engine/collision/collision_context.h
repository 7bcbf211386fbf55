#pragma once
// Per-thread scratch for collision queries: posed bodies and bounding boxes of every robot, object
// boxes, candidate lists, all allocated once. One context per thread; any number of contexts may query
// one CollisionWorld at once. A context is tied to the world it was made for.
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/collision/collision_report.h"
#include "engine/collision/collision_world.h"

namespace dash {

class CollisionContext {
 public:
  explicit CollisionContext(const CollisionWorld& world);

  const CollisionWorld& world() const { return *world_; }
  const CollisionCounters& counters() const { return counters_; }
  CollisionCounters& counters() { return counters_; }
  void resetCounters() { counters_ = {}; }

  /// Scratch written by the queries (internal to engine/collision; read-only for everyone else).
  struct PosedRobot {
    std::vector<Pose> frames;      ///< bodyFrames() output: each body's frame F in the world
    std::vector<Aabb> body_aabb;   ///< world box of each body
    Aabb aabb;                     ///< union of body_aabb
    int held_object = -1;          ///< object index when holding
    bool held_in_transit = false;  ///< HeldObject::in_transit
    Pose X_WO_held = Pose::Identity();
    Aabb held_aabb;
  };
  /// Which pairs one robot check looks at, when a segment query narrows them with swept boxes.
  struct Candidates {
    std::vector<int> obstacles;                ///< for the robot's bodies
    std::vector<int> held_obstacles;           ///< for its held object
    std::vector<int> objects;                  ///< resting objects, for bodies and held object
    std::vector<std::pair<int, int>> self_pairs;
    std::vector<int> held_vs_bodies;           ///< non-gripper bodies checked against the held object
    std::vector<int> robots;                   ///< robots standing still (posed), for bodies and held object
  };
  struct Scratch {
    std::vector<PosedRobot> robots;         ///< one per scene robot
    std::vector<std::uint8_t> resting;      ///< per object: rests and is considered in this query
    std::vector<int> resting_list;          ///< the objects with resting[j], in index order
    std::vector<Aabb> object_aabb;          ///< per object, valid where resting[j]
    std::vector<Pose> object_pose;          ///< per object, valid where resting[j]
    Candidates candidates;
    std::vector<Aabb> swept_body;           ///< segment queries: per body, for one interval
    std::vector<Aabb> step_boxes;           ///< segment queries: body and held boxes per visited step
    struct Interval {
      int lo, hi;          ///< step indices
      int slot_lo, slot_hi;  ///< their boxes in step_boxes
    };
    std::vector<Interval> intervals;        ///< segment queries: work queue, coarse to fine
    std::vector<double> displacement;       ///< segment queries: per body bound over the whole segment
    std::vector<int> robots_in_query;
  };
  Scratch& scratch() { return scratch_; }
  const Scratch& scratch() const { return scratch_; }

 private:
  const CollisionWorld* world_;
  CollisionCounters counters_;
  Scratch scratch_;
};

}  // namespace dash
