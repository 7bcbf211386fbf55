#pragma once
// Replanning in the composite space of the robots in a conflict (the subproblem of ARC, Solis et al.
// 2021, which the paper's Algorithm 3 uses): the robots' joint spaces are stacked into one space and
// planned together with OMPL's RRT-Connect, so that each robot may step aside for another. Validity is
// the multi-robot check: the robots of the subproblem against each other, the obstacles, the objects
// resting at that moment, and the other robots standing still. A straight composite segment moves
// every robot at the same fraction at any instant, which is what a synchronised time
// parameterisation (each segment as long as its slowest robot needs) executes.
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_state.h"
#include "engine/core/deadline.h"
#include "engine/scene/object_layout.h"

namespace dash {

struct CompositeProblem {
  std::vector<int> robots;            ///< the movers, each once
  std::vector<JointVector> start;     ///< per mover
  std::vector<JointVector> goal;      ///< per mover (a robot stepping aside has goal == start)
  std::vector<HeldObject> held;       ///< per mover, constant during the motion
  ObjectLayout layout;                ///< objects resting meanwhile
  std::vector<RobotState> parked;     ///< other robots, standing still throughout
};

struct CompositeParams {
  /// Work budget: RRT-Connect iterations (work, not time: the same on a loaded machine).
  std::size_t iterations = 5000;
  double seconds = 10.0;  ///< a ceiling on top of the work budget, within the deadline
  double range = 1.5;     ///< RRT-Connect step in the stacked joint space (radians)
  bool simplify = true;
};

/// A composite path: waypoints, each holding one configuration per mover (in problem.robots order),
/// from exactly problem.start to exactly problem.goal. nullopt if none was found in the budget.
using CompositePath = std::vector<std::vector<JointVector>>;

std::optional<CompositePath> planComposite(const CollisionWorld& world, CollisionContext& context,
                                           const CompositeProblem& problem, const CompositeParams& params,
                                           const Deadline& deadline);

}  // namespace dash
