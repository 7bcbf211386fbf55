#pragma once
// The task plan: an unvalidated schedule (paper) — the task-level actions in the order the query
// chose them, with the partial order that says which action must finish before which (an action
// depends on the actions that produced the elements it consumes). Independent threads of actions
// run in parallel: the plan is asynchronous.
#include <string>
#include <vector>

#include "engine/hypergraph/hypergraph_topology.h"
#include "engine/scene/object_layout.h"
#include "engine/task/task_arc.h"
#include "engine/task/task_space.h"

namespace dash {

struct TaskStep {
  HyperarcId arc;
  TaskArc action;
  std::vector<int> after;  ///< indices of earlier steps that must finish first
};

struct TaskPlan {
  std::vector<TaskStep> steps;  ///< a topological order of the partial order

  bool empty() const { return steps.empty(); }
  /// One line per step, for people: "  3. handover ur5e_0->ur5e_1 obj_2 (top->side)   after 1, 2".
  std::string describe(const TaskSpace& space) const;
  /// {"steps": [{"index", "type", "robot", "robot2", "object", "location", "grasp", "grasp2", "task",
  ///             "after": [...]}, ...]} with ids as in the scene.
  std::string toJson(const TaskSpace& space) const;
};

std::string describeStep(const TaskStep& step, const TaskSpace& space);

/// What rests where before each step of a plan and after its last one (steps + 1 entries).
struct RestingAlongPlan {
  std::vector<ObjectLayout> layouts;          ///< the resting objects' poses
  std::vector<std::vector<int>> locations;    ///< per object: its location in the TaskSpace, -1 while held
};
RestingAlongPlan restingAlong(const TaskPlan& plan, const TaskSpace& space);

}  // namespace dash
