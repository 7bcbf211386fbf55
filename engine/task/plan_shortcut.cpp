#include "engine/task/plan_shortcut.h"

#include <algorithm>

namespace dash {

namespace {

/// Index of the next step that puts `object` back down at `location` after `from`, or -1. Steps
/// marked in `gone` are skipped.
int nextReturn(const TaskPlan& plan, const std::vector<char>& gone, int from, int object, int location) {
  for (int k = from + 1; k < static_cast<int>(plan.steps.size()); ++k) {
    const TaskArc& a = plan.steps[k].action;
    if (gone[k] || a.object != object) continue;
    if (a.type == TaskArcType::kPlace && a.location == location) return k;
  }
  return -1;
}

/// Whether a step strictly between i and j (not one of the trip's) needs `at` off the frontier.
bool needsLocationFree(const TaskPlan& plan, const std::vector<char>& gone, const TaskHypergraph& graph,
                       const TaskConstraintSet& constraints, VertexId at, int i, int j, int object) {
  std::vector<VertexId> blocked;
  constraints.forEachOnPre(at, [&](const TaskConstraint& c) {
    if (c.kind == TaskConstraint::Kind::kFrontier) blocked.push_back(c.post);
  });
  if (blocked.empty()) return false;
  for (int k = i + 1; k < j; ++k) {
    if (gone[k] || plan.steps[k].action.object == object) continue;
    for (VertexId h : graph.graph().head(plan.steps[k].arc))
      if (std::find(blocked.begin(), blocked.end(), h) != blocked.end()) return true;
  }
  return false;
}

}  // namespace

void rebuildDependencies(TaskPlan& plan) {
  std::vector<int> last_robot, last_object;
  auto slot = [](std::vector<int>& v, int i) -> int& {
    if (static_cast<int>(v.size()) <= i) v.resize(static_cast<std::size_t>(i) + 1, -1);
    return v[static_cast<std::size_t>(i)];
  };
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    TaskStep& s = plan.steps[k];
    s.after.clear();
    auto depend = [&](int d) {
      if (d >= 0 && std::find(s.after.begin(), s.after.end(), d) == s.after.end()) s.after.push_back(d);
    };
    const TaskArc& a = s.action;
    if (a.robot >= 0) depend(slot(last_robot, a.robot));
    if (a.robot2 >= 0) depend(slot(last_robot, a.robot2));
    if (a.object >= 0) depend(slot(last_object, a.object));
    std::sort(s.after.begin(), s.after.end());
    if (a.robot >= 0) slot(last_robot, a.robot) = k;
    if (a.robot2 >= 0) slot(last_robot, a.robot2) = k;
    if (a.object >= 0) slot(last_object, a.object) = k;
  }
}

TaskPlan removeRoundTrips(const TaskPlan& plan, const TaskHypergraph& graph, const TaskConstraintSet& constraints,
                          int* removed) {
  if (removed) *removed = 0;
  for (const TaskStep& s : plan.steps)
    if (s.action.type == TaskArcType::kInspect) return plan;
  TaskPlan out = plan;
  // Passes until none removes anything: a trip may become removable once one inside it is gone.
  for (bool changed = true; changed;) {
    changed = false;
    std::vector<char> gone(out.steps.size(), 0);
    for (int i = 0; i < static_cast<int>(out.steps.size()); ++i) {
      const TaskArc& pick = out.steps[i].action;
      if (gone[i] || pick.type != TaskArcType::kPick) continue;
      const int j = nextReturn(out, gone, i, pick.object, pick.location);
      if (j < 0) continue;
      const auto at = graph.find(TaskElement::objectAt(pick.object, pick.location));
      if (!at || needsLocationFree(out, gone, graph, constraints, *at, i, j, pick.object)) continue;
      for (int k = i; k <= j; ++k)
        if (!gone[k] && out.steps[k].action.object == pick.object) {
          gone[k] = 1;
          if (removed) ++*removed;
        }
      changed = true;
    }
    if (!changed) break;
    std::vector<TaskStep> kept;
    for (std::size_t k = 0; k < out.steps.size(); ++k)
      if (!gone[k]) kept.push_back(std::move(out.steps[k]));
    out.steps = std::move(kept);
  }
  rebuildDependencies(out);
  return out;
}

}  // namespace dash
