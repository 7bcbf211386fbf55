#pragma once
// Internal to the plan validator (plan_validator.h): the robots' motion as the validator reads it,
// and the replay of the events into a timeline of who holds what and where the rest lie.
#include <cstdint>
#include <string>
#include <vector>

#include "engine/plan/plan.h"
#include "engine/plan/plan_validator.h"
#include "engine/scene/object_layout.h"
#include "engine/scene/scene.h"

namespace dash::validation {

/// Each scene robot's trajectory, or its home when the plan's is missing or has the wrong number of
/// joints (that is reported elsewhere; the robot is still there and still collides).
class PlanMotion {
 public:
  PlanMotion(const Scene& scene, const Plan& plan);

  const Scene& scene() const { return *scene_; }
  int robotCount() const { return static_cast<int>(trajectories_.size()); }
  /// nullptr when robot r holds still at home for the whole plan.
  const RobotTrajectory* trajectory(int r) const { return trajectories_[static_cast<std::size_t>(r)]; }
  JointVector q(int r, double t) const;
  Pose tcp(int r, double t) const;

 private:
  const Scene* scene_;
  std::vector<const RobotTrajectory*> trajectories_;
};

/// An object attached to a robot's TCP.
struct Holder {
  int robot = -1;
  Pose X_TO = Pose::Identity();
};

struct ObjectState {
  Pose X_WO = Pose::Identity();  ///< where it rests; meaningless while held
  std::vector<Holder> holders;   ///< holders[0] carries it; a second one is a handover in progress
  bool held() const { return !holders.empty(); }
};

/// The state from time `t` on, until the next epoch.
struct Epoch {
  double t = 0.0;
  std::vector<ObjectState> objects;  ///< Scene::objects order
  ObjectLayout layout;               ///< the resting objects
};

struct Timeline {
  std::vector<Epoch> epochs;  ///< epochs[0] is the start (t = 0); sorted by t, distinct times
  std::vector<std::uint8_t> task_done;  ///< per scene task: a legal inspect event happened
  std::vector<std::uint8_t> task_mentioned;  ///< per scene task: some inspect event names it

  /// The epoch in force at time t (events at t have happened).
  const Epoch& at(double t) const;
  int indexAt(double t) const;
};

/// World pose of object `object` at time t in `epoch` (carried: holders[0]'s TCP(t) * X_TO).
Pose objectPose(const Epoch& epoch, int object, const PlanMotion& motion, double t);

/// A number for messages: up to `digits` significant digits ("0.0123", "1.39").
std::string formatNumber(double x, int digits = 4);

/// Replays the plan's events in time order, appending a problem for each illegal one. An illegal
/// event still changes the state where that keeps later problems meaningful (a grasp at the wrong
/// pose still picks the object up); one that cannot (a release of an object not held) is skipped.
Timeline replayEvents(const Plan& plan, const PlanMotion& motion, const ValidationOptions& options,
                      std::vector<ValidationProblem>& problems);

}  // namespace dash::validation
