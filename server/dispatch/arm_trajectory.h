#pragma once
// One arm's goal in FollowJointTrajectory terms: joint names, points with positions, velocities and
// time from start, plus the gripper commands (the plan's grasp and release events for that robot).
//
// Between points the arm follows the cubic Hermite curve through the points' positions and
// velocities (what ROS's joint trajectory controller and UR's cubic SPLINE points do). The velocities
// come from the plan (velocitiesForPlanPath): where the plan keeps one constant velocity through a
// point, that velocity; elsewhere zero, so the arm comes to rest at every corner. Either way each
// segment's velocities are parallel to the segment, so the arm stays exactly on the plan's straight
// joint-space lines and passes every point at the plan's time; only the timing inside a segment that
// starts or ends at a corner differs (it eases in and out). That is the price of a dynamically
// feasible motion, and why peakSpeed() (up to 1.5x the plan's segment speed) is checked, not only
// the plan's own speeds.
#include <algorithm>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/robots/joint_vector.h"

namespace dash::dispatch {

struct TrajectoryWaypoint {
  JointVector positions;
  JointVector velocities;
  double time_from_start = 0.0;  ///< seconds
};

struct GripperCommand {
  enum class Action { kGrasp, kRelease };
  double t = 0.0;  ///< seconds from the start
  Action action = Action::kGrasp;
  std::string object;
};

const char* gripperActionName(GripperCommand::Action action);  ///< "grasp", "release"

struct ArmTrajectory {
  std::string robot;
  std::vector<std::string> joint_names;
  std::vector<TrajectoryWaypoint> points;  ///< strictly increasing time_from_start, the first at 0
  std::vector<GripperCommand> gripper;     ///< sorted by t

  double duration() const { return points.empty() ? 0.0 : points.back().time_from_start; }
  /// When the goal is over: the last point or the last gripper command, whichever is later.
  double endTime() const { return gripper.empty() ? duration() : std::max(duration(), gripper.back().t); }
  /// Position at time t (clamped to [0, duration]); the first point before, the last after.
  JointVector positionAt(double t) const;
  JointVector velocityAt(double t) const;
};

/// The arm trajectory of `robot` in `plan`, with every time multiplied by time_scale (> 0; 2 = half
/// speed). Throws InputError if the plan has no such robot.
ArmTrajectory armTrajectoryFromPlan(const Plan& plan, const std::string& robot, double time_scale = 1.0);

/// Point velocities for a piecewise-linear path: zero at the ends and at corners, the segment velocity
/// where two consecutive segments share it (relative tolerance 1e-9).
std::vector<JointVector> velocitiesForPlanPath(const std::vector<JointVector>& q, const std::vector<double>& t);

/// The fastest any joint moves, and where.
struct PeakSpeed {
  double speed = 0.0;     ///< |qdot|, rad/s or m/s
  double ratio = 0.0;     ///< speed / velocity_max of that joint
  int joint = -1;
  int segment = -1;       ///< segment i joins points i and i+1
};
/// Peak joint speeds of the Hermite curves, compared with per-joint limits (same size as the joints).
PeakSpeed peakSpeed(const ArmTrajectory& trajectory, const JointVector& velocity_max);

/// Structural check of a goal (what every driver checks before loading it): joint count, at least one
/// point, finite numbers, sizes, the first point at t = 0, strictly increasing times, gripper times
/// finite and not negative. Returns an empty string when fine, else the reason.
std::string structuralProblem(const ArmTrajectory& trajectory, int dof);

}  // namespace dash::dispatch
