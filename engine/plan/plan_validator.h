#pragma once
// The plan validator: checks a plan against every rule of the contract (formats.md, dashbench.plan/1)
// for its scene. A planner runs it before it reports a plan as solved; a plan that fails is a bug,
// never a result. `dashbench validate` runs it on files.
//
// What is checked (tolerances in ValidationOptions):
//  - header: format, status "solved", the scene's name, makespan = the last point or event time;
//  - trajectories: every scene robot present, no others; joint_names equal to the model's; times
//    strictly increasing from t = 0; the first point at home; every point within the position limits;
//    every segment within velocity_max; the last point at home unless the scene says end_at_home false;
//  - events, in time order (at one instant: grasps of an object another robot holds, then releases,
//    then other grasps, then inspects, so a handover may grasp and release at the same t): the robot
//    has the capability ("grasp" or the task's); a grasp needs TCP^-1 * object pose = X_TO, an object
//    that is not fixed, an empty hand, and at most one other holder (a handover); a release needs the
//    robot to hold the object and leaves it resting stably (scene/support.h) unless another robot still
//    holds it; while two robots hold one object, their attachments agree; an inspect needs the TCP at
//    the task pose while the requires_removed object is away from its start;
//  - geometry at every instant, certified (certified_geometry.h): between two point or event times
//    every robot moves on a straight joint-space segment; conservative advancement with exact
//    distances and per-body motion bounds proves each pair apart (robot-robot, robot-obstacle,
//    robot-object, held object against everything, self pairs) or finds where it is not, with the
//    depth. Contact is allowed only where it is meant (collision_world.h); every other pair must keep
//    `clearance` apart. GeometryCheck::kSampled is the older check (samples no body point moves more
//    than max_step apart, kept as the benchmark's baseline);
//  - the end: every object rests (none is still held), every object with a goal is at it, every task
//    has an inspect event.
//
// Departures and readings of the contract, on purpose:
//  - inspect checks the TCP position only (the contract: "within 5 mm"), not its orientation;
//  - handover agreement compares object positions only ("the same object pose (within 5 mm)");
//  - goal poses compare rotations exactly (no symmetry of cubes is assumed);
//  - an object left unsupported because the object beneath it was taken away is not reported: the
//    contract only asks a release to leave the object resting stably.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/scene/scene.h"

namespace dash {

enum class ProblemKind {
  // header
  kFormat,
  kStatus,
  kSceneName,
  kMakespan,
  // trajectories
  kRobotMissing,
  kRobotUnknown,
  kJointNames,
  kTimeOrder,
  kStartTime,
  kStartHome,
  kJointLimit,
  kVelocity,
  kEndHome,
  // events
  kEventReference,  ///< unknown robot, object or task
  kCapability,
  kFixedObject,
  kGraspPose,
  kGraspHeld,  ///< already held by this robot, or by two others
  kHandsFull,
  kHandover,  ///< two holders' attachments disagree
  kReleaseNotHeld,
  kReleaseUnstable,
  kInspectPose,
  kInspectNotRemoved,
  // geometry
  kSelfCollision,
  kRobotRobotCollision,
  kRobotObstacleCollision,
  kRobotObjectCollision,
  kHeldObjectCollision,
  kObjectObjectCollision,
  // end state
  kHeldAtEnd,
  kGoalNotReached,
  kTaskMissing,
};

/// Stable snake_case names ("grasp_pose", "robot_robot_collision", ...), used in JSON output.
const char* problemKindName(ProblemKind kind);

struct ValidationProblem {
  ProblemKind kind = ProblemKind::kFormat;
  double t = 0.0;      ///< when it happens (the first instant for one that lasts)
  double t_end = 0.0;  ///< the last sampled instant for one that lasts (collisions), else t
  std::string robot;   ///< the robot involved, if any
  std::string object;  ///< the object involved, if any
  std::string other;   ///< the other party (robot, obstacle, object, body), if any
  std::string message;
  /// Certified collisions: the smallest signed distance the pair reached (negative: the penetration
  /// depth; non-negative: closer than the clearance) and when. 0 and t otherwise.
  double distance = 0.0;
  double t_closest = 0.0;
};

/// The closest a pair of parts came over the plan (certified geometry only).
struct PairClearance {
  std::string a;  ///< a robot body ("ur5e_0.forearm") or a held object ("obj_3 (held by ur5e_0)")
  std::string b;  ///< an obstacle, object, or another robot's part
  double distance = 0.0;  ///< smallest signed distance found at a checked instant (m)
  double t = 0.0;
  bool contact_allowed = false;  ///< contact is meant (a gripper and a resting object, a held object and its support)
};

struct ValidationReport {
  std::vector<ValidationProblem> problems;  ///< sorted by time (stable)
  std::size_t samples = 0;                  ///< instants checked for collisions (pair evaluations when certified)
  /// Certified geometry: the smallest distance found between any pair that must keep the clearance
  /// (contact-meant pairs excluded), the pair and when; infinity when no pair came near another.
  PairClearance closest{.distance = std::numeric_limits<double>::infinity()};
  /// Certified geometry: per pair of parts whose swept boxes ever met, its smallest distance, closest first.
  std::vector<PairClearance> pairs;

  /// The geometric check was stopped (ValidationOptions::stop) before it covered the plan: not certified.
  bool stopped = false;

  bool valid() const { return problems.empty() && !stopped; }
  bool has(ProblemKind kind) const;
  int count(ProblemKind kind) const;
  /// One line per problem: "t=1.39 grasp_pose ur5e_0 obj_0: ...".
  std::string summary() const;
};

struct ValidationOptions {
  double time_tolerance = 1e-6;        ///< s: makespan, t = 0 start; events closer than this share an instant
  double home_tolerance = 1e-6;        ///< rad or m per joint: start and end at home
  double limit_tolerance = 1e-6;       ///< rad or m per joint: position limits
  double velocity_tolerance = 1e-6;    ///< relative, on velocity_max
  double grasp_position_tolerance = 0.005;   ///< m
  double grasp_rotation_tolerance = 0.05;    ///< rad
  double handover_tolerance = 0.005;         ///< m
  double inspect_position_tolerance = 0.005; ///< m
  double removed_distance = 0.05;            ///< m: "away from its start"
  double goal_position_tolerance = 0.01;     ///< m
  double goal_rotation_tolerance = 0.05;     ///< rad
  enum class GeometryCheck { kCertified, kSampled };
  GeometryCheck geometry = GeometryCheck::kCertified;
  double clearance = 0.0;  ///< m: every pair not in contact by design keeps at least this apart (certified)
  /// m of motion: conservative advancement never splits finer; a pair that stays within this of the
  /// clearance is taken as clear (the certificate's resolution).
  double certify_floor = 5e-5;
  double max_step = 0.01;  ///< m: sampled check: the most any body point moves between consecutive samples;
                           ///< certified check: handover attachment agreement is sampled this finely
  bool check_geometry = true;
  /// Threads of the geometric check; 0 = the hardware's. The report (problems, their order, counts,
  /// clearances) is the same for any number: planners feed its first problem back.
  int threads = 0;
  /// Polled before each stretch of the certified check (from every worker thread): true stops it, and
  /// the report says `stopped`. A planner passes its deadline, so that validation ends with the run.
  std::function<bool()> stop;
};

/// Checks `plan` against `scene`. Never throws for a bad plan: every violation is a problem.
ValidationReport validatePlan(const Scene& scene, const Plan& plan, const ValidationOptions& options = {});

}  // namespace dash
