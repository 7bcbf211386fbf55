#pragma once
// Transition configurations the motion layer could not reach: both ends of the missing move were
// collision-free, yet the robot's roadmap found no way to the configuration (often an IK branch that a
// roadmap hardly connects to, such as a wrist flipped the other way); or conflict resolution could not
// schedule a handover at them. Task conflict detection then samples another configuration for the same
// transition instead of the task query banning the transition (paper, "Motion Planning Layer": a
// transition becomes a constraint only after resampling).
#include <cstddef>
#include <utility>
#include <vector>

#include "engine/robots/joint_vector.h"

namespace dash {

class RejectedConfigurations {
 public:
  /// Configurations closer than this (max joint difference, radians) count as the same one: task
  /// conflict detection samples deterministically, so a repeat is the very same vector.
  static constexpr double kSameTolerance = 1e-6;

  /// False if q was rejected already.
  bool add(int robot, const JointVector& q) {
    if (contains(robot, q)) return false;
    configs_.emplace_back(robot, q);
    return true;
  }
  bool contains(int robot, const JointVector& q) const {
    for (const auto& [r, rejected] : configs_)
      if (r == robot && rejected.size() == q.size() && (rejected - q).cwiseAbs().maxCoeff() < kSameTolerance)
        return true;
    return false;
  }
  std::size_t size() const { return configs_.size(); }

 private:
  std::vector<std::pair<int, JointVector>> configs_;
};

}  // namespace dash
