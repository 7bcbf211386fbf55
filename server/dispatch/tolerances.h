#pragma once
// Path and goal tolerances as ros2_control's joint trajectory controller defines them
// (constraints.<joint>.trajectory, constraints.<joint>.goal, constraints.goal_time): per joint, a path
// tolerance on |actual - planned| at the same time while the trajectory runs, a goal tolerance on
// |actual - last point| once it has ended, and a goal time tolerance: how long after the end time the
// arm may take to get within its goal tolerance. A tolerance of 0 is not checked (as in the
// controller). A violation names the joint, the amount and the time.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "engine/robots/joint_vector.h"

namespace dash::dispatch {

/// One tolerance for every joint, with per-joint overrides by joint name.
struct ToleranceSpec {
  double all = 0.0;                      ///< rad (m) for joints not listed
  std::map<std::string, double> joints;  ///< joint name -> rad (m)

  double forJoint(const std::string& name) const;
  /// The tolerance of each of `joint_names`, in their order.
  JointVector resolve(const std::vector<std::string>& joint_names) const;
  /// Throws InputError (naming `what`) on a negative or non-finite value.
  void validate(const std::string& what) const;
  /// Throws InputError (naming `what`.NAME) for a per-joint name not among `known`: a typo would
  /// otherwise silently fall back to `all`.
  void validateJointNames(const std::set<std::string>& known, const std::string& what) const;
};

/// Defaults a real UR5e meets at the speeds the pre-flight allows. The path tolerance is that of UR's
/// own ROS 2 driver (ur_controllers.yaml: trajectory 0.2 rad per joint): servoj with a 0.03 s
/// look-ahead lags its target by a few tens of milliseconds, about 0.1 rad at the UR5e's 3.14 rad/s.
/// The goal tolerance is tighter than the driver's 0.1 rad: the arm settles to well under 0.01 rad
/// within the goal time.
inline constexpr double kDefaultPathTolerance = 0.2;
inline constexpr double kDefaultGoalTolerance = 0.01;
inline constexpr double kDefaultGoalTimeTolerance = 1.0;

/// The worst joint of |actual - reference| against per-joint tolerances (0 = unchecked).
struct ToleranceCheck {
  bool violated = false;
  int joint = -1;          ///< the joint exceeding its tolerance by the most (or the largest error)
  double error = 0.0;      ///< |actual - reference| of that joint
  double tolerance = 0.0;  ///< that joint's tolerance
};
ToleranceCheck checkTolerance(const JointVector& actual, const JointVector& reference, const JointVector& tolerance);

/// "joint 2 (elbow_joint) 0.2345 rad off at t=1.234 s (path tolerance 0.2000)"-style text.
std::string describeViolation(const ToleranceCheck& check, const std::vector<std::string>& joint_names,
                              const std::string& kind, double t);

}  // namespace dash::dispatch
