#include "engine/dash/motion_constraint.h"

#include <algorithm>

namespace dash {

namespace {
bool contains(std::span<const VertexId> set, VertexId v) { return std::find(set.begin(), set.end(), v) != set.end(); }

/// v on the frontier after applying a: produced by it, or there before and not consumed.
bool presentAfter(const MotionGraph& graph, const HyperpathState& state, HyperarcId a, VertexId v) {
  if (contains(graph.head(a), v)) return true;
  return state.inFrontier(v) && !contains(graph.tail(a), v);
}
}  // namespace

bool violates(const MotionGraph& graph, const HyperpathState& state, HyperarcId a, const MotionConstraint& c) {
  if (c.edge.valid()) {
    if (a != c.edge) return false;
    // The edge is traversed while the interval holds: during is there before or after it.
    return !c.during.valid() || state.inFrontier(c.during) || contains(graph.head(a), c.during);
  }
  if (!c.vertex.valid()) return false;
  // Only a hyperarc that brings the robot to the vertex, or brings the interval about while the robot
  // is there, can break a vertex constraint.
  const bool robot_there = presentAfter(graph, state, a, c.vertex);
  if (!robot_there) return false;
  return !c.during.valid() || presentAfter(graph, state, a, c.during);
}

std::vector<HyperarcId> alwaysForbidden(const std::vector<MotionConstraint>& constraints) {
  std::vector<HyperarcId> out;
  for (const MotionConstraint& c : constraints)
    if (c.edge.valid() && !c.during.valid()) out.push_back(c.edge);
  return out;
}

std::string describe(const MotionHypergraph& graph, const MotionConstraint& c) {
  std::string s = graph.space().scene().robots[c.robot].id + " not ";
  s += c.edge.valid() ? "on " + graph.label(c.edge) : "at " + graph.label(c.vertex);
  s += c.during.valid() ? " while " + graph.label(c.during) : " at any time";
  return s;
}

}  // namespace dash
