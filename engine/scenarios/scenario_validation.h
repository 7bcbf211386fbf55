#pragma once
// The promise every generated scene keeps: it passes the checks of `dashbench check-scene`
// (findSceneProblems: no collisions at home, at the start or at the goal, every object resting, every
// object graspable at its start and goal), every object has a chain of robots with feasible handover
// poses from a robot that can grasp its start to one that can grasp its goal, and every inspect task
// pose is reachable by a robot with the capability while the task's lid is away.
//
// Blocked on purpose: in the shelf families a rear slot is reachable only while the slots in front of
// it are empty (that is the point of those scenarios), so "graspable at the goal" among all goals
// fails for a rear object by design. A generator lists such grasps as BlockedGrasp; for them the
// grasp check is made without the objects named as blockers, and the matching check-scene line is
// replaced by that check. Nothing else is relaxed.
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
  bool handover_chains = true;      ///< every object with a goal needs a chain of robots (UR families)
  HandoverSearch handover_search;   ///< where handovers are looked for
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
  std::vector<std::string> problems;     ///< empty: the scene keeps the promise
  std::vector<ObjectTransfer> transfers;  ///< movable objects with a goal (when handover_chains)
  HandoverGraph graph;                    ///< the robot graph used (when handover_chains)
  bool ok() const { return problems.empty(); }
};

/// The layout in which findSceneProblems tests grasps at the goal: objects with a goal at it, fixed
/// objects where they are, other movable objects left out.
ObjectLayout goalCheckLayout(const Scene& scene);

/// All checks above. Problems are one human-readable line each.
ScenarioReport validateScenario(const Scene& scene, const ValidationSpec& spec);

}  // namespace dash
