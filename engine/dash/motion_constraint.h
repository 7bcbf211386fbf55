#pragma once
// CBS-MP's constraints (Solis, Motes, Sandström, Amato, RA-L 2021) on DaSH's motion hypergraph H_M: a
// constraint is indexed by (robot, vertex or edge, time interval). The robot may not be at the vertex
// (a configuration of H_M) or traverse the edge (a move or transition hyperarc of H_M) during the
// interval. Time in the combined query is the hyperpath's partial order, not clock time, so an
// interval is named by the H_M vertex whose presence delimits it: the constraint holds while that
// vertex is on the frontier (from the hyperarc that produces it to the one that consumes it), e.g.
// "while object o rests at placement p" for a conflict with a resting object, or "while o waits in the
// state this step consumes" for a schedule conflict. An invalid `during` is the whole plan.
// The frontier alone decides a constraint, so the query's state memo stays exact under constraints.
#include <string>
#include <vector>

#include "engine/dash/motion_hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"

namespace dash {

struct MotionConstraint {
  int robot = -1;
  VertexId vertex;   ///< the robot may not be here during the interval (or:)
  HyperarcId edge;   ///< the robot may not traverse this hyperarc during the interval
  VertexId during;   ///< the interval: while this vertex is on the frontier (invalid: always)
  bool operator==(const MotionConstraint&) const = default;
  bool operator<(const MotionConstraint& o) const {
    return std::tie(robot, vertex, edge, during) < std::tie(o.robot, o.vertex, o.edge, o.during);
  }
};

/// Whether applying `a` in `state` breaks `c`: after it, the robot would be at c.vertex (or it
/// traverses c.edge) while c.during is on the frontier.
bool violates(const MotionGraph& graph, const HyperpathState& state, HyperarcId a, const MotionConstraint& c);

/// Constraints that hold over the whole plan (during invalid) with an edge: the query leaves these
/// hyperarcs out of its cost-to-go too.
std::vector<HyperarcId> alwaysForbidden(const std::vector<MotionConstraint>& constraints);

std::string describe(const MotionHypergraph& graph, const MotionConstraint& c);

}  // namespace dash
