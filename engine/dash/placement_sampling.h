#pragma once
// DaSH pre-samples object placements besides each object's start and goal, without asking whether a
// plan will need them (paper, "Analysis and Discussion": DaSH "pre samples object poses without
// reasoning about their necessity"): per object, stable poses on a support surface near a robot that
// can take it from its start or put it at its goal, clear of obstacles and of every known object
// location (footprints never overlap), graspable there by that robot; each becomes an extra location
// of the object in the TaskSpace. Where the room runs out (the lab's small sanitisation zone), an
// object shares a placement of another object of its size: DaSH's object elements are location-free,
// and a shared placement holds one object at a time (the combined query never places onto an
// occupied one). Sharing is the fallback only: objects queueing for one spot serialise a plan.
#include "engine/core/rng.h"
#include "engine/task/geometric_reachability.h"
#include "engine/task/task_space.h"

namespace dash {

struct PlacementSamplingParams {
  int per_object = 1;     ///< placements per object besides its start and goal
  double radius = 0.75;   ///< metres from the base of a robot that can take the object
  double spacing = 0.09;  ///< least centre distance to every other known object location
};

void presamplePlacements(TaskSpace& space, GeometricReachability& reach, TransitionSampler& sampler, Rng& rng,
                         const PlacementSamplingParams& params);

}  // namespace dash
