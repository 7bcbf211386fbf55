#pragma once
// The fast reject of the collision queries (issue 38): the covers of link_cover.h, posed for
// kBatchLanes configurations of a robot at once (batch_kinematics.h), checked against the pairs a
// query would check exactly (obstacle and object boxes, self pairs, other robots, held objects).
// A lane is cleared only when every one of those pairs is apart by the covers; the exact check then
// finds that configuration free too, so skipping it changes no answer and no report. Not for use
// outside engine/collision.
#include <cstdint>
#include <span>
#include <vector>

#include "engine/collision/collision_internal.h"
#include "engine/collision/cover_kernels.h"

namespace dash {

/// Whether the queries use the covers (default on; DASHBENCH_COVER=off in the environment turns it
/// off at start). Plans, answers and reports are the same either way; only the time differs.
bool coverFastPath();
void setCoverFastPath(bool on);

namespace detail {

/// The fast path for queries on `world`: on for the process and for that world.
inline bool coverOn(const CollisionWorld& world) { return world.usesCover() && coverFastPath(); }

inline constexpr int kCoverMaxBodies = 16;

/// One robot's covers in the world for every lane of a batch, and their boxes over all lanes.
struct RobotCoverBatch {
  int robot = -1;
  int bodies = 0;
  bool holding = false;
  cover::SegmentLanes body[kCoverMaxBodies];
  double radius_static[kCoverMaxBodies];
  double radius_robot[kCoverMaxBodies];
  Aabb body_box[kCoverMaxBodies];  ///< over the lanes, at radius_static
  cover::SegmentLanes held;
  double held_static = 0.0;
  double held_robot = 0.0;
  Aabb held_box;
  Aabb whole;  ///< bodies and held object
};

/// Covers of robot r at the frames of a batch, holding `held` (its X_TO) in every lane.
void coverFromFrames(const CollisionWorld& world, int r, const FrameBatch& frames, const HeldObject& held,
                     RobotCoverBatch& out);

/// Covers of robot r as posed in the context's scratch (the same in every lane).
void coverFromPosed(const CollisionWorld& world, const CollisionContext& context, int r, RobotCoverBatch& out);

/// clear[l] = 0 for the lanes where robot `c.robot` may meet a pair of `candidates` (the pairs that
/// checkPosedRobot looks at; `others` holds the covers of candidates.robots, in that order).
void clearAgainstCandidates(const CollisionWorld& world, const CollisionContext& context, const RobotCoverBatch& c,
                            const CandidateView& candidates, std::span<const RobotCoverBatch> others, double* clear);

/// clear[l] = 0 for the lanes where two robots may meet (bodies and held objects, as checkPosedRobotPair).
void clearRobotPair(const RobotCoverBatch& x, const RobotCoverBatch& y, double* clear);

// ---- One posed configuration: pair by pair, before an FCL call (false unless coverOn(world)) ----

/// Body b of posed robot r (cover at the whole clearance) apart from the box (X_WO, half extents).
bool bodyBoxApart(const CollisionWorld& world, const CollisionContext& context, int r, int b, const Pose& X_WO,
                  const Vec3& half);
/// Body b1 of posed robot r1 apart from body b2 of posed robot r2 (half the clearance each; r1 == r2 for
/// a self pair).
bool bodiesApart(const CollisionWorld& world, const CollisionContext& context, int r1, int b1, int r2, int b2);
/// The object held by posed robot r (cover at the whole clearance) apart from the box.
bool heldBoxApart(const CollisionWorld& world, const CollisionContext& context, int r, const Pose& X_WO,
                  const Vec3& half);
/// The object held by posed robot `holder` apart from body b of posed robot r.
bool heldBodyApart(const CollisionWorld& world, const CollisionContext& context, int holder, int r, int b);
/// The objects held by posed robots r1 and r2 apart.
bool heldObjectsApart(const CollisionWorld& world, const CollisionContext& context, int r1, int r2);

// ---- Segments (cover_segments.cpp) ----------------------------------------------------------------

/// cleared[k] = 1 for the steps k in 1 .. n-1 of robot start.robot's straight segment start.q -> q_end
/// (at t = k / n, holding start.held) that the covers clear against `view` (whose `robots` are posed
/// in the context's scratch); 0 for the others and for k = 0 and n.
void coverSegmentSteps(const CollisionWorld& world, const CollisionContext& context, const RobotState& start,
                       const JointVector& q_end, int n, const CandidateView& view, std::vector<std::uint8_t>& cleared);

/// The same for simultaneous straight motions, all at t = k / n: each robot against the pairs of `scope`
/// (fullCandidates; none with kRobotsOnly), and, unless kObjectsOnly, each pair of moving robots and
/// each moving robot against the posed robots `parked`.
void coverMotionSteps(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> starts,
                      std::span<const JointVector> ends, CheckScope scope, std::span<const int> parked, int n,
                      std::vector<std::uint8_t>& cleared);

/// The lanes still clear, as bits (lane l = bit l), among the first `lanes`.
std::uint32_t clearedLanes(const double* clear, int lanes);

}  // namespace detail
}  // namespace dash
