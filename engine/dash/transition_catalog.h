#pragma once
// DaSH's transition sampling: configurations for EVERY transition of H_T before any query (DaSH
// "pre-samples feasible configurations for each transition", paper, "Overview"). For each pick/place
// hyperarc (robot, object, class): grasp configurations at every placement of the object (start,
// goal, pre-sampled); for each handover hyperarc (giver, receiver, object, class pair) and each grasp
// of that class the giver can actually hold the object with: an object pose between the two arms, a
// giver configuration holding it so and a receiver grasp configuration, the two free of each other; for each inspect hyperarc: inspection
// configurations. Every configuration (and its approach/retreat, backed off along the TCP axis on a
// straight TCP line, rising a little when sideways: backOffPose, cartesianPath) is checked against
// what never moves: these are the eager checks of DaSH. Resting objects and other
// robots are left to conflict resolution.
#include <vector>

#include "engine/core/deadline.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/task/transition_sampler.h"

namespace dash {

/// A grasp of one object at one placement: used by the pick there and by the place there.
struct GraspSample {
  int robot = -1;
  int object = -1;
  int placement = -1;  ///< location index in the TaskSpace
  GraspClass grasp = GraspClass::kTop;
  HeldObject held;     ///< the object and X_TO while held
  JointVector q;       ///< at the object
  JointVector q_pre;   ///< backed off with an empty hand: approach before a pick, retreat after a place
  JointVector q_hold;  ///< backed off holding it: retreat after a pick, approach before a place
  /// q -> q_pre and q -> q_hold: the TCP's straight lines as waypoints (cartesian_path.h).
  std::vector<JointVector> pre_path;
  std::vector<JointVector> hold_path;
};

struct HandoverSample {
  int giver = -1;
  int receiver = -1;
  int object = -1;
  GraspClass grasp = GraspClass::kTop;   ///< giver's class
  GraspClass grasp2 = GraspClass::kTop;  ///< receiver's class
  Pose X_WO = Pose::Identity();          ///< the object at the handover
  HeldObject held;                       ///< giver's grasp
  HeldObject held2;                      ///< receiver's grasp
  JointVector q1;       ///< giver at the handover (it brings the object straight there)
  JointVector q1_post;  ///< giver backed off, empty hand
  JointVector q2;       ///< receiver at the handover
  JointVector q2_pre;   ///< receiver backed off, empty hand
  JointVector q2_post;  ///< receiver backed off, holding
  /// q1 -> q1_post, q2 -> q2_pre and q2 -> q2_post as straight TCP lines (cartesian_path.h).
  std::vector<JointVector> q1_post_path;
  std::vector<JointVector> q2_pre_path;
  std::vector<JointVector> q2_post_path;
};

struct InspectSample {
  int robot = -1;
  int task = -1;
  JointVector q;
  JointVector q_pre;  ///< approach start and retreat end
  std::vector<JointVector> pre_path;  ///< q -> q_pre, a straight TCP line (cartesian_path.h)
};

// The same candidates as Lazy-DaSH's task conflict detection and motion layer (TaskConflictParams,
// MotionLayerParams): the paper names no difference between the planners' transition sampling.
struct TransitionCatalogParams {
  int grasps_per_class = 6;          ///< grasp configurations per (robot, object, placement, class)
  /// Object poses of the first search per handover hyperarc for a new receiver grasp (the whole grid):
  /// when it finds none, the hyperarc is impossible (as Lazy-DaSH's handoverPossible cache concludes).
  int handover_poses = 1040;
  /// Object poses of every other search: for a grasp the receiver already has (DaSH's own chaining,
  /// which Lazy-DaSH does not need as it samples per plan step), or on a hyperarc already found
  /// possible: the start of the same grid.
  int targeted_handover_poses = 16;
  int handovers_per_grasp = 2;       ///< handover samples per handover hyperarc and giver grasp
  int inspect_configs = 2;           ///< per inspect hyperarc
  double approach_distance = 0.06;   ///< metres the TCP backs off along its approach axis
  double side_lift = 0.015;          ///< metres a sideways back-off also rises (backOffPose)
  /// Side grasps (into a shelf cubby) back off by the farthest of these that is free, as Lazy-DaSH's
  /// motion layer does when the short back-off is not reached: DaSH anchors its roadmaps there.
  std::vector<double> deep_approach_distances = {0.15, 0.2, 0.25, 0.3, 0.35};
  bool approach_line = true;         ///< side grasps prefer an IK branch with a free approach line
};

struct TransitionCatalog {
  std::vector<GraspSample> grasps;
  std::vector<HandoverSample> handovers;
  std::vector<InspectSample> inspects;
};

/// Samples every transition of `graph`. Stops early (with what it has) when the deadline passes.
TransitionCatalog sampleTransitions(TransitionSampler& sampler, const TaskSpace& space, const DashTaskGraph& graph,
                                    const TransitionCatalogParams& params, const Deadline& deadline);

}  // namespace dash
