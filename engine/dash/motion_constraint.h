#pragma once
// CBS-MP's constraints (Solis, Motes, Sandström, Amato, RA-L 2021) on DaSH's motion hypergraph H_M: a
// constraint is (robot, vertex or edge, time interval [t0, t1] in seconds of the schedule). The robot
// may not be at the vertex (a configuration of H_M) or traverse the edge (a move or transition
// hyperarc of H_M) during the interval. A conflict found at time t between robots a and b gives the two
// children of the constraint tree one constraint each, for a and for b, over the conflict's interval.
//
// Who honours what: the combined query has no clock (a hyperpath is a partial order), so it honours
// the constraints that hold over the whole plan ([0, +inf): the vertex or edge is never used). DaSH
// schedules with the shared Scheduler (engine/conflict): there a timed constraint is a window in which
// the robot's step that uses the vertex or edge may not happen; the robot waits until t1, as SIPP's
// safe intervals do (StepWindow; stepWindows below maps the constraints onto an extracted plan).
//
// DaSH also treats resting objects as obstacles that move over the plan (resting_conflicts.h). Those
// conflicts are found before any time is assigned, so their interval is named in the hyperpath's
// order: `while_resting`, the H_M vertex of the object resting in the way; the constraint holds while
// that vertex is on the frontier. The frontier alone decides these, so the query's state memo stays
// exact under constraints.
#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <vector>

#include "engine/conflict/scheduler.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/plan_extraction.h"
#include "engine/hypergraph/hyperpath_search.h"

namespace dash {

struct MotionConstraint {
  static constexpr double kEnd = std::numeric_limits<double>::infinity();  ///< t1 of "to the end of the plan"
  int robot = -1;
  VertexId vertex;   ///< the robot may not be here during the interval (or:)
  HyperarcId edge;   ///< the robot may not traverse this hyperarc during the interval
  double t0 = 0.0;   ///< the interval, seconds of the schedule: [t0, t1]
  double t1 = kEnd;
  VertexId while_resting;  ///< resting-object conflicts: the interval is while this vertex is on the frontier

  /// The interval is the whole plan: the query keeps the robot off the vertex or edge altogether.
  bool wholePlan() const { return !while_resting.valid() && t0 <= 0.0 && std::isinf(t1); }
  /// A clock-time window the Scheduler honours (StepWindow).
  bool timed() const { return !while_resting.valid() && !wholePlan(); }
  bool operator==(const MotionConstraint&) const = default;
  bool operator<(const MotionConstraint& o) const {
    return std::tie(robot, vertex, edge, t0, t1, while_resting) <
           std::tie(o.robot, o.vertex, o.edge, o.t0, o.t1, o.while_resting);
  }
};

/// Whether applying `a` in `state` breaks `c` as far as the query can tell: after it, the robot would be
/// at c.vertex (or it traverses c.edge) while c.while_resting is on the frontier, or at all for a
/// whole-plan constraint. Timed constraints are the Scheduler's: never broken here.
bool violates(const MotionGraph& graph, const HyperpathState& state, HyperarcId a, const MotionConstraint& c);

/// Constraints over the whole plan with an edge: the query leaves these hyperarcs out of its cost-to-go too.
std::vector<HyperarcId> alwaysForbidden(const std::vector<MotionConstraint>& constraints);

/// The timed constraints as windows on the steps of `plan` (StepWindow): a constraint applies to each
/// step whose transit (moves) or transition uses its edge or vertex for its robot, and to the robot's
/// way home when its moves there do.
std::vector<StepWindow> stepWindows(const MotionGraph& graph, const ExtractedPlan& plan,
                                    const std::vector<MotionConstraint>& constraints);

/// "ur5e_0 not on move ...; t in [1.250, 1.500] s" (the constraint event's content; the window is
/// written as Lazy-DaSH writes a motion constraint's).
std::string describe(const MotionHypergraph& graph, const MotionConstraint& c);

}  // namespace dash
