#pragma once
// Sanity checks of a loaded scene (the `dashbench check-scene` command, and generators that want to
// vet what they made). Each problem is one human-readable line naming the robots, objects and
// obstacles involved; findSceneProblemsDetailed gives the same problems with their kind and ids, so
// callers never have to parse the wording.
#include <string>
#include <vector>

#include "engine/scene/scene.h"

namespace dash {

/// One problem of a scene.
struct SceneProblem {
  enum class Kind {
    kRobotAtHomeCollides,    ///< ids: the robot, then what it hits
    kRobotsAtHomeCollide,    ///< ids: the two robots
    kObjectCollides,         ///< ids: the object, then what it hits
    kObjectNotResting,       ///< ids: the object
    kObjectNotGraspable,     ///< ids: the object
  };
  /// The layout the problem was found in: objects at their start, or at their goal.
  enum class Moment { kStart, kGoal };

  Kind kind = Kind::kObjectCollides;
  Moment moment = Moment::kStart;
  std::string message;           ///< the line `dashbench check-scene` prints
  std::vector<std::string> ids;  ///< scene ids of the robots, objects and obstacles involved, subject first
};

/// What is checked:
///  - robots at home against themselves, obstacles, objects at their start poses and each other; if the
///    plan must end at home, also against the objects at their goals;
///  - objects against obstacles and each other, at the start and at the goal (goal layout: objects with
///    a goal at it, fixed objects where they are, other movable objects left out: they may go anywhere);
///  - every object resting stably at its start, and every goal (engine/scene/support.h);
///  - every movable object graspable at its start and at its goal by some robot with the "grasp"
///    capability: a grasp candidate (grasp_candidates.h) with an IK solution that is collision-free
///    while holding the object, among the obstacles and the fixed objects only. Other movable objects
///    are not in the way for this check: a plan may move them first or place them later. So a rear
///    shelf slot that the object in front of it blocks at the goal is fine (the rear one goes in
///    first: that ordering is what the Shelf-wall and Stocking families test), while a slot blocked by
///    an obstacle or a fixed object is reported.
std::vector<SceneProblem> findSceneProblemsDetailed(const Scene& scene);

/// The messages of findSceneProblemsDetailed, in the same order.
std::vector<std::string> findSceneProblems(const Scene& scene);

}  // namespace dash
