#pragma once
// The first stage of DaSH's conflict resolution (CBS-MP, Solis et al. 2021, with the objects as
// obstacles that move over the plan): every robot's part of an extracted plan is checked against the
// objects resting at that point of the plan's order. A colliding move is replanned by the low-level
// search under that constraint: the robot's validated roadmap with the resting objects in the way
// (ValidatedRoadmap::plan). What cannot be resolved there comes back as a conflict naming the motion
// hyperarcs involved, for the constraint tree: a transition whose configurations touch a resting
// object (no replanning moves a sampled configuration), or a move with no way round. Its constraint
// (motion_constraint.h) keeps the robot off that configuration or hyperarc while the object in the
// way rests where it does.
// Robot-robot conflicts are the Scheduler's (engine/conflict), shared with Lazy-DaSH.
#include <optional>
#include <string>
#include <vector>

#include "engine/dash/motion_constraint.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/plan_extraction.h"

namespace dash {

struct MotionConflict {
  enum class Kind { kTransition, kMove, kSchedule };
  Kind kind = Kind::kMove;
  int step = -1;                   ///< plan step (-1: the way home)
  std::vector<int> robots;         ///< robots whose motions are involved
  std::vector<HyperarcId> arcs;    ///< the motion hyperarcs involved
  /// CBS-MP: one child of the constraint tree per entry, each adding that constraint.
  std::vector<MotionConstraint> constraints;
  std::string what;
};

struct RestingConflictStats {
  int replans = 0;  ///< moves replanned round resting objects
};

/// Shortens every transit and way home of `plan` in place (what never moves only: the robot, its held
/// object, obstacles): the straight segment when it is free, else greedy shortcuts along the path.
/// The roadmap's shortest paths zigzag through milestones; Lazy-DaSH's motion layer tries the
/// straight segment first too, so both planners hand the scheduler comparable motions. Returns the
/// number of paths shortened.
int shortcutPaths(ExtractedPlan& plan, const CollisionWorld& world, CollisionContext& context);

/// Checks and repairs `plan` in place; the first conflict it could not resolve, if any.
std::optional<MotionConflict> resolveRestingConflicts(ExtractedPlan& plan, const MotionHypergraph& graph,
                                                      const CollisionWorld& world, CollisionContext& context,
                                                      RoadmapSet& roadmaps, const Deadline& deadline,
                                                      RestingConflictStats& stats);

}  // namespace dash
