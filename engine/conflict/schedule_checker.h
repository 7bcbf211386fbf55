#pragma once
// Motion conflict detection in continuous time (paper, "Motion Conflicts"): a new timed piece of one
// robot against everything already scheduled — hyperarc-hyperarc conflicts with other robots' motions
// and hyperarc-vertex conflicts with resting objects. Time is cut at every breakpoint of every
// timeline, so inside each sub-interval all robots move linearly and the resting objects are fixed;
// each sub-interval is then checked at the collision checker's segment resolution.
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/conflict/timeline.h"

namespace dash {

struct ScheduleConflict {
  double t = 0.0;   ///< start of the sub-interval where it was found
  int other = -1;   ///< the other robot, or -1 for a resting object / obstacle
  int object = -1;  ///< the resting object, if that was it
  int robot = -1;   ///< the robot whose motion was checked (-1: a resting object was checked)
};

class ScheduleChecker {
 public:
  ScheduleChecker(const CollisionWorld& world, CollisionContext& context);

  /// Robot `robot` following `timeline` over [from, until] (until may be kForever: then up to the
  /// end of everything scheduled), against the other timelines and the resting objects.
  std::optional<ScheduleConflict> check(const RobotTimeline& timeline, double from, double until,
                                        const std::vector<RobotTimeline>& others, const ObjectTimeline& objects);
  /// Object `object` resting at X_WO from `from` on, against every robot timeline but `except`.
  std::optional<ScheduleConflict> checkResting(int object, const Pose& X_WO, double from,
                                               const std::vector<RobotTimeline>& timelines, int except);
  /// From now on every check also cuts time at t, so the robots' configurations at exactly t are checked
  /// (a contact the plan validator found there, between the instants this checker sampled).
  void alsoCheckAt(double t);

 private:
  bool mayInteract(int a, int b) const { return interact_[a][b]; }

  const CollisionWorld* world_;
  CollisionContext* context_;
  std::vector<std::vector<bool>> interact_;  ///< robots whose reach boxes (grown for a held object) meet
  std::vector<double> extra_cuts_;           ///< alsoCheckAt's instants, sorted
};

}  // namespace dash
