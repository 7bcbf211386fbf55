#pragma once
// Motion constraints C_M = (Pi_1, Pi_2, p) of Lazy-DaSH (paper, "Query (Motion-extended Hypergraph)"
// and "Motion Conflict Resolution and Constraint Feedback"): the histories that lead to the motions
// in conflict (one robot's, or two robots') and the region p where they conflict. Histories are named
// by their last element, the task step each robot was doing (plus the task plan they belong to, by
// the round that made them); the region is either configurations to stay out of (a transition
// configuration the motion query found no way to, a handover that conflict resolution could not
// schedule) or an instant in time (a contact the validator found between the scheduler's check
// instants). They are respected by the next motion query on the same task plan (task conflict
// detection samples other transition configurations outside the region) and by conflict resolution
// (the scheduler checks the instants of the region from then on).
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/robots/joint_vector.h"
#include "engine/scene/scene.h"

namespace dash {

struct MotionConstraint {
  struct History {
    int robot = -1;
    int step = -1;  ///< the task step the robot's history ends with (-1: its way home)
  };
  std::vector<History> histories;                            ///< Pi_1 (and Pi_2)
  std::vector<std::pair<int, JointVector>> configurations;   ///< region p: (robot, configuration)
  double t_begin = -1.0, t_end = -1.0;                       ///< region p: a time window (validator contact)
  std::string cause;

  bool hasTimeRegion() const { return t_begin >= 0.0; }
  /// "ur5e_0 at step 3, ur5e_1 at step 3; region: 2 configurations" (the constraint event's content).
  std::string describe(const Scene& scene) const;
};

/// The motion constraints of a run, in the order they were learned.
class MotionConstraintSet {
 public:
  /// Adds c; returns its index (the constraint event's id).
  std::uint32_t add(MotionConstraint c) {
    constraints_.push_back(std::move(c));
    return static_cast<std::uint32_t>(constraints_.size() - 1);
  }
  const std::vector<MotionConstraint>& all() const { return constraints_; }
  std::size_t size() const { return constraints_.size(); }

 private:
  std::vector<MotionConstraint> constraints_;
};

}  // namespace dash
