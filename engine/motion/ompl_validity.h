#pragma once
// The OMPL side of our collision checks, shared by every planner that hands OMPL a joint space
// (Lazy-PRM roadmaps, DaSH's validated PRM, composite-space replanning): joint vectors in and out of
// RealVector states, and validity given as two predicates. Include only from .cpp files that use OMPL.
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <functional>
#include <memory>

#include "engine/robots/joint_vector.h"
#include "engine/robots/robot_model.h"

namespace dash {

/// The joint space a robot is planned in: its model's limits, revolute joints kept inside [-pi, pi]
/// (the range of inverseKinematics), samplers seeded from the planner run (seeded_ompl.h).
std::shared_ptr<ompl::base::RealVectorStateSpace> jointSpace(const RobotModel& model);

/// The first `dof` values of a RealVector state.
JointVector jointsOf(const ompl::base::State* s, int dof);
/// Writes q into the first q.size() values of a RealVector state.
void setJoints(const JointVector& q, ompl::base::State* s);

using StatePredicate = std::function<bool(const ompl::base::State*)>;
using MotionPredicate = std::function<bool(const ompl::base::State*, const ompl::base::State*)>;

/// Installs the state validity checker and the straight-motion validator of `si`. Planners here only
/// need the yes/no answer of a motion check; when asked for the last valid state it reports the start.
void installValidity(const ompl::base::SpaceInformationPtr& si, StatePredicate state_valid,
                     MotionPredicate motion_valid);

}  // namespace dash
