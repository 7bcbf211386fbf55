#pragma once
// Move-out poses for Lazy-DaSH's task space expansion (paper, Sec. "Task Planning Layer": when the
// task constraints contradict each other, the task space grows extra stable states), and for
// resampling one that no grasp chain can use ("resampling is performed to search for valid
// alternatives"). A pose is sampled on a support surface near the base of a robot that can take the
// object at its start, clear of the object locations already known.
//
// A pose is a trap for a robot that takes the object at its start and can grasp it at the pose, but
// with no grasp it takes it with, or with no grasp it takes there that also fits at the goal: H_T offers
// that robot the move-out, and no grasp chain of its own serves it (a side grasp out of a shelf cubby
// has no twin on a low table). With `one_grasp` (the planner parameter
// move_out_one_grasp, beyond the paper), poses that trap no robot are looked for first.
#include <optional>
#include <vector>

#include "engine/core/rng.h"
#include "engine/placement/placement_region.h"
#include "engine/task/geometric_reachability.h"
#include "engine/task/task_conflict_detection.h"
#include "engine/task/task_space.h"
#include "engine/task/transition_sampler.h"

namespace dash {

struct MoveOutPose {
  Pose X_WO = Pose::Identity();
  int surface = -1;  ///< index into Scene::surfaces
};

class MoveOutSampler {
 public:
  struct Rule {
    bool one_grasp = true;        ///< a pose that traps no robot (see the header comment)
    bool clear_of_extras = true;  ///< clear of the other move-out poses too, not only of starts and goals
  };

  /// All references must outlive the sampler. `one_grasp` off: the trap-free passes are skipped.
  MoveOutSampler(const TaskSpace& space, TransitionSampler& sampler, GeometricReachability& reachability,
                 const TaskConflictParams& grasps, bool one_grasp);

  /// A pose for a new move-out state of `object`, by three passes of `attempts` samples per robot:
  /// trap-free and clear of every known location; then any that the robot can grasp, clear of every
  /// known location; then the same, clear of the anchored locations (starts and goals) alone.
  std::optional<MoveOutPose> forExpansion(int object, Rng& rng) const;
  /// A new pose for move-out state `location` of `object` that no grasp chain could use: trap-free,
  /// clear of every known location (the old pose included), then trap-free beside other move-outs; with
  /// one_grasp off, nullopt (task conflict detection then resamples on the same surface).
  std::optional<MoveOutPose> forResample(int object, Rng& rng) const;

 private:
  std::optional<MoveOutPose> search(int object, const std::vector<Rule>& rules, Rng& rng) const;
  std::vector<int> takers(int object) const;
  std::optional<MoveOutPose> sample(int object, int r, Rule rule, const std::vector<int>& takers, Rng& rng) const;
  bool trapsNoTaker(int object, const std::vector<int>& takers, const Pose& X_WO) const;
  bool carriesWithOneGrasp(int robot, int object, const Pose& from, const Pose& to) const;
  bool graspsAt(int robot, int object, const Pose& X_WO) const;

  const TaskSpace* space_;
  TransitionSampler* sampler_;
  GeometricReachability* reachability_;
  TaskConflictParams grasps_;
  bool one_grasp_;
  std::vector<PlacementRegion> regions_;
};

}  // namespace dash
