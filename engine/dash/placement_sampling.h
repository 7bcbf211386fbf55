#pragma once
// DaSH pre-samples object placements besides each object's start and goal, without asking whether a
// plan will need them (paper, "Analysis and Discussion": DaSH "pre samples object poses without
// reasoning about their necessity"). Its object elements are location-free, so a placement is a
// place any object of a size may rest at: per robot that can grasp and per object size, stable poses
// on a support surface near the robot, clear of obstacles and of every known object location
// (footprints never overlap), graspable there by that robot. Each becomes an extra location of every
// object of that size in the TaskSpace; two objects resting at one placement at once is a conflict
// the planner's conflict resolution finds (a transition touching a resting object).
#include "engine/core/rng.h"
#include "engine/task/geometric_reachability.h"
#include "engine/task/task_space.h"

namespace dash {

struct PlacementSamplingParams {
  int per_robot = 1;      ///< placements per grasping robot and object size
  double radius = 0.75;   ///< metres from the robot's base
  double spacing = 0.09;  ///< least centre distance to every other known object location
};

void presamplePlacements(TaskSpace& space, GeometricReachability& reach, TransitionSampler& sampler, Rng& rng,
                         const PlacementSamplingParams& params);

}  // namespace dash
