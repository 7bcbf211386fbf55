#pragma once
// The promise every generated scene keeps: it passes the checks of `dashbench check-scene`
// (findSceneProblems: no collisions at home, at the start or at the goal, every object resting, every
// object graspable at its start and goal among obstacles and fixed objects), every movable object is
// also graspable with the other objects in place (at the start, or at their goals) except for the
// blockers its generator declares, every object has a chain of robots with feasible handover poses
// from a robot that can grasp its start to one that can grasp its goal, and every inspect task pose is
// reachable by a robot with the capability while the task's lid is away.
//
// Blocked on purpose: in the shelf families a rear slot is reachable only while the slots in front of
// it are empty (that is the point of those scenarios). check-scene accepts that (movable objects are
// never in the way of its grasp check); the generator's own, stricter check lists such grasps as
// BlockedGrasp and makes them without the objects named as blockers. Nothing else is relaxed.
#include <string>
#include <vector>

#include "engine/scenarios/handover_graph.h"
#include "engine/scene/scene.h"

namespace dash {

/// A grasp of `object` at its start or goal that the objects `blockers` prevent by design.
struct BlockedGrasp {
  int object = -1;
  bool at_goal = true;
  std::vector<int> blockers;
};

struct ValidationSpec {
  bool handover_chains = true;     ///< every object with a goal needs a chain of robots (UR families)
  HandoverSearch handover_search;  ///< where handovers are looked for
  std::vector<BlockedGrasp> blocked;
};

/// How one object travels: who can grasp it at each end, and the least number of handovers between.
struct ObjectTransfer {
  int object = -1;
  std::vector<int> start_robots;
  std::vector<int> goal_robots;
  int min_handovers = -1;  ///< -1: no chain
};

struct ScenarioReport {
  std::vector<std::string> problems;      ///< empty: the scene keeps the promise
  std::vector<ObjectTransfer> transfers;  ///< movable objects with a goal (when handover_chains)
  HandoverGraph graph;                    ///< the robot graph used (when handover_chains)
  bool ok() const { return problems.empty(); }
};

/// The goal layout of findSceneProblems' collision checks, and of the generator's grasp check at the
/// goal: objects with a goal at it, fixed objects where they are, other movable objects left out.
ObjectLayout goalCheckLayout(const Scene& scene);

/// All checks above. Problems are one human-readable line each.
ScenarioReport validateScenario(const Scene& scene, const ValidationSpec& spec);

}  // namespace dash
