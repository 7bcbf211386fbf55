#include "engine/dash/schedule_conflicts.h"

#include <algorithm>
#include <utility>

namespace dash {

namespace {

/// The robot's own vertex in the tail of hyperarc a, and the first tail vertex that is not its own
/// (the object or handover partner the transition waits for: the interval of a schedule constraint).
std::pair<VertexId, VertexId> ownAndOtherTail(const MotionGraph& g, HyperarcId a, int robot) {
  VertexId own, other;
  for (VertexId v : g.tail(a)) {
    const MotionVertex& mv = g.property(v);
    const bool robot_vertex = mv.kind == MotionVertex::Kind::kRobot || mv.kind == MotionVertex::Kind::kHolding;
    if (robot_vertex && mv.robot == robot) own = v;
    else if (!other.valid()) other = v;
  }
  return {own, other};
}

}  // namespace

MotionConflict scheduleConflict(const MotionHypergraph& graph, const ExtractedPlan& plan, int step,
                                const std::string& why) {
  MotionConflict c;
  c.kind = MotionConflict::Kind::kSchedule;
  c.step = step;
  c.what = why;
  if (step >= 0) {
    const TaskStep& s = plan.plan.steps[step];
    const int participants = s.action.type == TaskArcType::kHandover ? 2 : 1;
    for (int role = 0; role < participants; ++role) {
      const int robot = role == 0 ? s.action.robot : s.action.robot2;
      const auto& moves = plan.step_moves[step][role];
      c.robots.push_back(robot);
      const HyperarcId arc = moves.empty() ? s.arc : moves.back();
      if (std::find(c.arcs.begin(), c.arcs.end(), arc) == c.arcs.end()) c.arcs.push_back(arc);
      MotionConstraint k;
      k.robot = robot;
      k.edge = arc;
      k.during = ownAndOtherTail(graph.graph(), s.arc, robot).second;
      c.constraints.push_back(k);
    }
    return c;
  }
  for (int r = 0; r < static_cast<int>(plan.home_moves.size()); ++r)
    if (!plan.home_moves[r].empty()) {
      c.robots.push_back(r);
      c.arcs.push_back(plan.home_moves[r].back());
      c.constraints.push_back(MotionConstraint{r, {}, plan.home_moves[r].back(), {}});
    }
  return c;
}

bool isContact(const ValidationProblem& problem) {
  return problem.kind == ProblemKind::kRobotRobotCollision || problem.kind == ProblemKind::kHeldObjectCollision ||
         problem.kind == ProblemKind::kRobotObjectCollision;
}

int contactStep(const Scene& scene, const TaskPlan& plan, const std::vector<double>& step_times,
                const ValidationProblem& problem) {
  if (!isContact(problem) || step_times.size() != plan.steps.size()) return -1;
  auto involved = [&](int r) {
    return r >= 0 && (scene.robots[r].id == problem.robot || scene.robots[r].id == problem.other);
  };
  int after = -1, before = -1;
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    if (!involved(plan.steps[k].action.robot) && !involved(plan.steps[k].action.robot2)) continue;
    if (step_times[k] >= problem.t && (after < 0 || step_times[k] < step_times[after])) after = k;
    if (step_times[k] < problem.t && (before < 0 || step_times[k] > step_times[before])) before = k;
  }
  return after >= 0 ? after : before;
}

}  // namespace dash
