#pragma once
// Which robots can pass an object to which, from the geometry alone: the robot graph whose edges are
// pairs of robots with a collision-free mid-air handover pose, the robots that can grasp an object at
// a pose, and the least number of handovers that links them. Generators use it to vet a layout
// (every object needs a chain of robots from its start to its goal); tests use it to show that the
// Sorting family needs more handovers as it grows.
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/scene/object_layout.h"

namespace dash {

/// Where a handover is looked for: object positions around the midpoint of the two bases, nearest
/// first. Offsets are along the base-to-base line, across it, and heights above the higher base.
struct HandoverSearch {
  std::vector<double> along = {0.0, -0.1, 0.1, -0.2, 0.2};
  std::vector<double> across = {0.0, -0.15, 0.15, -0.3, 0.3};
  std::vector<double> heights = {0.35, 0.25, 0.45, 0.6};
};

/// One feasible handover: the object at X_WO held by both robots at once.
struct HandoverPose {
  int giver = -1;
  int receiver = -1;
  Pose X_WO = Pose::Identity();
  GraspCandidate giver_grasp;
  GraspCandidate receiver_grasp;
  JointVector q_giver;
  JointVector q_receiver;
};

/// A handover of scene object `object` between robots r1 and r2 in free space (obstacles and the two
/// robots; no resting objects), or nullopt if none of the searched poses works.
std::optional<HandoverPose> findHandover(const CollisionWorld& world, CollisionContext& context, int r1, int r2,
                                         int object, const HandoverSearch& search = {});

/// The undirected robot graph for handing over `object` (robots with the "grasp" capability only).
struct HandoverGraph {
  std::vector<std::vector<int>> adjacent;  ///< per robot, sorted
  std::vector<HandoverPose> edges;         ///< one witness per edge, r1 < r2, in (r1, r2) order

  bool linked(int r1, int r2) const;
};

HandoverGraph buildHandoverGraph(const CollisionWorld& world, CollisionContext& context, int object,
                                 const HandoverSearch& search = {});

/// Robots with the "grasp" capability that can hold `object` at X_WO (some grasp candidate with a
/// collision-free IK solution among obstacles and the resting objects of `layout`), in index order.
std::vector<int> robotsAbleToGrasp(const CollisionWorld& world, CollisionContext& context, int object, const Pose& X_WO,
                                   const ObjectLayout& layout);

/// Least number of handovers from a robot of `from` to a robot of `to` (0 if they share one), or -1 if
/// no chain links them.
int minHandovers(const HandoverGraph& graph, const std::vector<int>& from, const std::vector<int>& to);

/// An upper bound on the distance from a robot's base origin to its TCP, over all configurations.
double maxTcpReach(const RobotModel& model);

}  // namespace dash
