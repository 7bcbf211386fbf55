#pragma once
// Sanity checks of a loaded scene (the `dashbench check-scene` command, and generators that want to
// vet what they made). Each problem is one human-readable line naming the robots, objects and
// obstacles involved.
#include <string>
#include <vector>

#include "engine/scene/scene.h"

namespace dash {

/// What is checked:
///  - robots at home against themselves, obstacles, objects at their start poses and each other; if the
///    plan must end at home, also against the objects at their goals;
///  - objects against obstacles and each other, at the start and at the goal (goal layout: objects with
///    a goal at it, fixed objects where they are, other movable objects left out: they may go anywhere);
///  - every object resting stably at its start, and every goal (engine/scene/support.h);
///  - every movable object graspable at its start and goal by some robot with the "grasp" capability:
///    a grasp candidate (grasp_candidates.h) with an IK solution that is collision-free while holding
///    the object, among obstacles and the other objects of that layout.
std::vector<std::string> findSceneProblems(const Scene& scene);

}  // namespace dash
