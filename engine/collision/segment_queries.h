#pragma once
// Straight joint-space segments q0 -> q1 (the motion between two plan points, formats.md), checked at
// discrete configurations dense enough that no point of any robot body, of the TCP or of a held object
// moves more than `resolution` (1 cm) between two checked configurations.
//
// The bound is derived from the kinematic chain and holds at every configuration: for joint i, lever_i
// is the largest distance from its axis to any point that joint moves (RobotGeometry::body_lever, plus
// the held object's reach from the TCP); a point moves at most sum_i |dq_i| * lever_i along the whole
// segment, so steps = ceil(sum_i |dq_i| * lever_i / resolution), per body, taking the largest.
//
// Cheap tests come first: the end points, then a swept box per body (its boxes at q0 and q1 grown by
// half its displacement bound, which contains every intermediate pose). Only obstacles, objects and
// self pairs that meet a swept box are checked at the intermediate configurations, coarse to fine
// (midpoint first) so that collisions are found early.
#include <span>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_report.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"
#include "engine/scene/object_layout.h"

namespace dash {

inline constexpr double kSegmentResolution = 0.01;  ///< metres

struct SegmentOptions {
  CheckScope scope = CheckScope::kAll;
  bool check_endpoints = true;  ///< false when the caller has already checked both end configurations
  double resolution = kSegmentResolution;
};

/// Upper bound on how far any point of robot r's bodies, TCP or held object moves along q0 -> q1.
double segmentDisplacementBound(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                                const HeldObject& held);

/// Upper bound on how far any point of body b of robot r moves along q0 -> q1.
double bodyDisplacementBound(const CollisionWorld& world, int robot, int body, const JointVector& q0,
                             const JointVector& q1);

/// Upper bound on how far any point of the object `held` moves along q0 -> q1 (0 for an empty hand).
double heldDisplacementBound(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                             const HeldObject& held);

/// Intervals the segment is cut into: ceil(bound / resolution), at least 1.
int segmentSteps(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                 const HeldObject& held, double resolution = kSegmentResolution);

/// One robot moving from start.q to q_end, holding start.held throughout, among resting objects.
/// On a collision, report->segment_fraction says where (0 = start, 1 = end).
bool segmentInCollision(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                        const JointVector& q_end, const ObjectLayout& layout, CollisionReport* report = nullptr,
                        const SegmentOptions& options = {});

/// Whether an empty gripper enters the contact box of a resting object anywhere along q0 -> q1 (robot
/// `robot`, objects of `layout`), by conservative advancement on FCL signed distances between its
/// exact gripper bodies and the objects' contact boxes: at a distance d the next look is d / L further
/// along (L bounds how far any point of the body moves over the whole segment), down to a floor of
/// kAdvanceFloor of motion. The object a gripper grasps or has just let go is checked against its
/// contact box with no clearance (collision_queries.h), so the sampled checks can miss a finger
/// sliding into it between two instants: a deep back-off's joint-space line bulges (stocking 3/18
/// seed 1: 6 mm off the straight approach at 30 cm, 0.35 mm into the box), which the certified
/// validator then rejects. This finds it where the approach is made.
inline constexpr double kAdvanceFloor = 5e-5;  ///< metres
bool gripperEntersContactBox(const CollisionWorld& world, CollisionContext& context, int robot, const JointVector& q0,
                             const JointVector& q1, const ObjectLayout& layout);

/// Per body of robot start.robot (its model's order), then its held object when it holds one: a world
/// box containing that part at every configuration of q0 -> q1 (its boxes at both ends grown by half its
/// displacement bound). Appended to `boxes`.
void sweptPartBoxes(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                    const JointVector& q_end, std::vector<Aabb>& boxes);

/// One robot's part of a simultaneous motion.
struct RobotMotion {
  RobotState start;
  JointVector q_end;
};

/// Several robots moving over the same time interval, each interpolated linearly from start to end
/// (all at the same fraction at any instant). Robots whose swept boxes meet no other robot's are
/// checked alone (not at all with CheckScope::kRobotsOnly: they cannot meet); otherwise all are
/// checked together at the finest step count of any robot.
bool motionsInCollision(const CollisionWorld& world, CollisionContext& context, std::span<const RobotMotion> motions,
                        const ObjectLayout& layout, CollisionReport* report = nullptr,
                        const SegmentOptions& options = {});

/// The motions as in motionsInCollision, among robots standing still (`parked`, each holding what it
/// holds): each moving robot is also checked against the parked robots (bodies and held objects) whose
/// boxes meet its swept box. The parked robots are posed once and checked against nothing else
/// (obstacles, objects, each other): they were when they stopped there. The motion planners' query with
/// other robots parked: a parked robot is never re-posed at every step.
bool motionsAmongParked(const CollisionWorld& world, CollisionContext& context, std::span<const RobotMotion> motions,
                        std::span<const RobotState> parked, const ObjectLayout& layout,
                        CollisionReport* report = nullptr, const SegmentOptions& options = {});

}  // namespace dash
