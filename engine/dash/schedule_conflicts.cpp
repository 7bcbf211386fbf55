#include "engine/dash/schedule_conflicts.h"

#include <algorithm>
#include <utility>

namespace dash {


namespace {

/// Robot `robot`'s last move into step `step` (its transition when it did not move; its last move home
/// at step -1; invalid when it has none).
HyperarcId moveInto(const ExtractedPlan& plan, int robot, int step) {
  if (step < 0) {
    const auto& home = plan.home_moves[static_cast<std::size_t>(robot)];
    return home.empty() ? HyperarcId() : home.back();
  }
  const TaskStep& s = plan.plan.steps[static_cast<std::size_t>(step)];
  const int role = s.action.robot == robot ? 0 : (s.action.robot2 == robot ? 1 : -1);
  if (role < 0) return {};
  const auto& moves = plan.step_moves[static_cast<std::size_t>(step)][static_cast<std::size_t>(role)];
  return moves.empty() ? s.arc : moves.back();
}

void addConstraint(MotionConflict& c, const MotionConstraint& k) {
  if (!k.edge.valid() || std::find(c.constraints.begin(), c.constraints.end(), k) != c.constraints.end()) return;
  c.robots.push_back(k.robot);
  if (std::find(c.arcs.begin(), c.arcs.end(), k.edge) == c.arcs.end()) c.arcs.push_back(k.edge);
  c.constraints.push_back(k);
}

/// The step-less conflict of old: the step's participants (or every robot's way home) over the whole plan.
void untimedConstraints(MotionConflict& c, const ExtractedPlan& plan, int step) {
  if (step >= 0) {
    const TaskStep& s = plan.plan.steps[static_cast<std::size_t>(step)];
    for (int robot : {s.action.robot, s.action.robot2})
      if (robot >= 0) addConstraint(c, {robot, {}, moveInto(plan, robot, step)});
    return;
  }
  for (int r = 0; r < static_cast<int>(plan.home_moves.size()); ++r) addConstraint(c, {r, {}, moveInto(plan, r, -1)});
}

}  // namespace

MotionConflict scheduleConflict(const MotionHypergraph&, const ExtractedPlan& plan, int step, const std::string& why,
                                const std::optional<ConflictRegion>& timing) {
  MotionConflict c;
  c.kind = MotionConflict::Kind::kSchedule;
  c.step = step;
  c.what = why;
  if (timing && timing->robot >= 0) {
    // CBS-MP: the conflict at [t_begin, t_end] between robots a and b: one child keeps a out of its
    // step over that interval, the other keeps b out of its own.
    for (const auto& [robot, k] : {std::pair{timing->robot, timing->step}, std::pair{timing->other, timing->other_step}}) {
      if (robot < 0) continue;
      MotionConstraint constraint{robot, {}, moveInto(plan, robot, k)};
      constraint.t0 = timing->t_begin;
      constraint.t1 = timing->t_end;
      addConstraint(c, constraint);
    }
  }
  if (c.constraints.empty()) untimedConstraints(c, plan, step);
  return c;
}

std::optional<ConflictRegion> contactTiming(const Scene& scene, const TaskPlan& plan,
                                            const std::vector<double>& step_times, const ValidationProblem& problem,
                                            double dwell, double min_window) {
  if (!isContact(problem) || step_times.size() != plan.steps.size()) return std::nullopt;
  auto stepAt = [&](int r) {
    for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
      const TaskArc& a = plan.steps[k].action;
      if ((a.robot == r || a.robot2 == r) && step_times[k] + dwell >= problem.t) return k;
    }
    return -1;
  };
  ConflictRegion timing;
  timing.robot = scene.robotIndex(problem.robot);
  timing.other = problem.other.empty() ? -1 : scene.robotIndex(problem.other);
  if (timing.robot < 0) std::swap(timing.robot, timing.other);
  if (timing.robot < 0) return std::nullopt;
  timing.step = stepAt(timing.robot);
  if (timing.other >= 0) timing.other_step = stepAt(timing.other);
  timing.t_begin = problem.t;
  timing.t_end = std::max(problem.t_end, problem.t + min_window);
  return timing;
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
