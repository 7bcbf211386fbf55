#pragma once
// What the task layer may assume about robots and objects when it builds H_T. Reachability ignores
// motion feasibility (paper: "the reachability only indicates that the object is within the graspable
// range of some robots"); handovers are lazily assumed feasible for robots within range, and task
// conflict detection finds out when they are not (the Wall case).
#include <functional>

#include "engine/geometry/pose.h"
#include "engine/task/task_element.h"

namespace dash {

struct TaskReachability {
  /// Robot r can grasp object o resting at X_WO with some grasp of class g (IK and static obstacles).
  std::function<bool(int robot, int object, const Pose& X_WO, GraspClass g)> canGrasp;
  /// Robot `giver` holding o with class g1 and robot `receiver` taking it with class g2 may hand over.
  std::function<bool(int giver, int receiver, int object, GraspClass g1, GraspClass g2)> canHandover;
  /// Robot r can bring its TCP to task k's inspection pose.
  std::function<bool(int robot, int task)> canInspect;
  /// Distance-based cost estimates for the greedy query (paper: base-to-object for grasps,
  /// base-to-base for handovers).
  std::function<double(int robot, const Pose& X_WO)> graspCost;
  std::function<double(int giver, int receiver)> handoverCost;
};

/// Grasp classes a handover may combine: the two hands must approach from different directions
/// (two top or two bottom grasps would put both grippers in the same place).
bool handoverClassesCompatible(GraspClass giver, GraspClass receiver);

}  // namespace dash
