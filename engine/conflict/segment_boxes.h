#pragma once
// The swept volumes of the scheduled pieces, indexed by robot and timeline segment (issue 38 item 2):
// conflict resolution (paper, "Motion Conflicts") checks a new timed piece of one robot against another
// robot's only where their time intervals overlap (ScheduleChecker cuts both timelines at their
// breakpoints) AND their swept volumes meet. The volume of a piece is bounded by the box of the
// timeline segment it lies in: the union of sweptPartBoxes (segment_queries.h) of the segment, for each
// object the robot holds at some instant of it, grown by kBoxSlack. Those part boxes contain every
// robot body and held object grown by the whole clearance (more than the half clearance robot-robot
// checks grow them by) at every configuration of the straight segment, hence at every configuration a
// check of a piece of it looks at: two pieces whose boxes are apart cannot conflict, and the exact
// check would find them free. A segment's box is computed once and kept while the segment (its ends,
// times and what is held along it) stays the same; a rewound and re-appended timeline gets new boxes.
#include <cstdint>
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/conflict/timeline.h"

namespace dash {

/// Metres each segment box is grown by beyond its parts' boxes: the rounding of the interpolated piece
/// ends (RobotTimeline::at) and of forward kinematics, many orders of magnitude below it.
inline constexpr double kBoxSlack = 1e-7;

/// What a robot holds, appended to an exact key: the object, the transit flag and (when holding) the
/// grasp pose's rotation and translation columns.
void appendHeldKey(std::vector<double>& key, const HeldObject& held);

class SegmentBoxes {
 public:
  SegmentBoxes(const CollisionWorld& world, CollisionContext& context);

  /// A world box containing every part of `timeline`'s robot (bodies, and whatever it holds) at every
  /// configuration of its straight piece [u, v], when [u, v] lies in one segment of the timeline (two
  /// consecutive points, or the standing after the last point); nullopt otherwise (then nothing is
  /// known and the piece must be checked).
  std::optional<Aabb> pieceBox(const RobotTimeline& timeline, double u, double v);
  /// Segment boxes computed so far (each segment once while it stays the same).
  std::uint64_t computed() const { return computed_; }

 private:
  struct Entry {
    bool valid = false;
    double ta = 0.0, tb = 0.0;
    JointVector qa, qb;
    std::vector<double> holds;  ///< what is held along it (object, transit flag, grasp pose)
    Aabb box;
  };
  /// What the robot holds at some instant of [ta, tb], as a key, into `key`.
  static void holdsKey(const RobotTimeline& timeline, double ta, double tb, std::vector<double>& key);
  /// The box of robot r moving qa -> qb while holding, in turn, each object of `timeline` held in [ta, tb].
  Aabb segmentBox(const RobotTimeline& timeline, const JointVector& qa, const JointVector& qb, double ta, double tb);

  const CollisionWorld* world_;
  CollisionContext* context_;
  std::vector<std::vector<Entry>> entries_;  ///< [robot][segment]
  std::vector<double> key_;                  ///< scratch
  std::vector<Aabb> parts_;                  ///< scratch
  std::uint64_t computed_ = 0;
};

}  // namespace dash
