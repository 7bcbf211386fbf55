#include "engine/dash/motion_constraint.h"

#include <algorithm>
#include <cstdio>

namespace dash {

namespace {
bool contains(std::span<const VertexId> set, VertexId v) { return std::find(set.begin(), set.end(), v) != set.end(); }

/// v on the frontier after applying a: produced by it, or there before and not consumed.
bool presentAfter(const MotionGraph& graph, const HyperpathState& state, HyperarcId a, VertexId v) {
  if (contains(graph.head(a), v)) return true;
  return state.inFrontier(v) && !contains(graph.tail(a), v);
}

/// Whether hyperarc a uses the constraint's edge, or brings its robot to (or from) its vertex.
bool uses(const MotionGraph& graph, HyperarcId a, const MotionConstraint& c) {
  if (c.edge.valid()) return a == c.edge;
  return c.vertex.valid() && (contains(graph.head(a), c.vertex) || contains(graph.tail(a), c.vertex));
}
}  // namespace

bool violates(const MotionGraph& graph, const HyperpathState& state, HyperarcId a, const MotionConstraint& c) {
  if (c.timed()) return false;  // the Scheduler's (StepWindow)
  if (c.edge.valid()) {
    if (a != c.edge) return false;
    // The edge is traversed while the interval holds: while_resting is there before or after it.
    return c.wholePlan() || state.inFrontier(c.while_resting) || contains(graph.head(a), c.while_resting);
  }
  if (!c.vertex.valid()) return false;
  // Only a hyperarc that brings the robot to the vertex, or brings the interval about while the robot
  // is there, can break a vertex constraint.
  const bool robot_there = presentAfter(graph, state, a, c.vertex);
  if (!robot_there) return false;
  return c.wholePlan() || presentAfter(graph, state, a, c.while_resting);
}

std::vector<HyperarcId> alwaysForbidden(const std::vector<MotionConstraint>& constraints) {
  std::vector<HyperarcId> out;
  for (const MotionConstraint& c : constraints)
    if (c.edge.valid() && c.wholePlan()) out.push_back(c.edge);
  return out;
}

std::vector<StepWindow> stepWindows(const MotionGraph& graph, const ExtractedPlan& plan,
                                    const std::vector<MotionConstraint>& constraints) {
  std::vector<StepWindow> out;
  auto add = [&](const MotionConstraint& c, int step) {
    const StepWindow w{c.robot, step, c.t0, c.t1};
    if (std::find(out.begin(), out.end(), w) == out.end()) out.push_back(w);
  };
  for (const MotionConstraint& c : constraints) {
    if (!c.timed()) continue;
    for (int k = 0; k < static_cast<int>(plan.plan.steps.size()); ++k) {
      const TaskArc& a = plan.plan.steps[k].action;
      const int role = a.robot == c.robot ? 0 : (a.robot2 == c.robot ? 1 : -1);
      if (role < 0) continue;
      const std::vector<HyperarcId>& moves = plan.step_moves[k][role];
      const bool used = uses(graph, plan.plan.steps[k].arc, c) ||
                        std::any_of(moves.begin(), moves.end(), [&](HyperarcId m) { return uses(graph, m, c); });
      if (used) add(c, k);
    }
    if (c.robot >= 0 && c.robot < static_cast<int>(plan.home_moves.size())) {
      const std::vector<HyperarcId>& home = plan.home_moves[c.robot];
      if (std::any_of(home.begin(), home.end(), [&](HyperarcId m) { return uses(graph, m, c); })) add(c, -1);
    }
  }
  return out;
}

std::string describe(const MotionHypergraph& graph, const MotionConstraint& c) {
  std::string s = graph.space().scene().robots[c.robot].id + " not ";
  s += c.edge.valid() ? "on " + graph.label(c.edge) : "at " + graph.label(c.vertex);
  if (c.while_resting.valid()) return s + " while " + graph.label(c.while_resting);
  if (c.wholePlan()) return s + " at any time";
  char window[64];
  if (std::isinf(c.t1)) std::snprintf(window, sizeof window, "; t in [%.3f, inf] s", c.t0);
  else std::snprintf(window, sizeof window, "; t in [%.3f, %.3f] s", c.t0, c.t1);
  return s + window;
}

}  // namespace dash
