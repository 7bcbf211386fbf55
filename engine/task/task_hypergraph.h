#pragma once
// The task space hypergraph H_T (paper, "Representation Construction (Task Space Hypergraph)"):
// built from the initial elements (robots alone, objects at their start) by applying pick, place,
// handover and inspect until no new element appears. A source hyperarc leads to the start elements
// and a sink hyperarc leaves the goal elements. Building is incremental: after a task space expansion
// the same call adds only what is new, so ids stay stable across iterations.
#include <functional>
#include <string>
#include <vector>

#include "engine/hypergraph/hypergraph.h"
#include "engine/task/reachability.h"
#include "engine/task/task_arc.h"
#include "engine/task/task_element.h"
#include "engine/task/task_space.h"

namespace dash {

using TaskGraph = Hypergraph<TaskElement, TaskArc>;

class TaskHypergraph {
 public:
  /// Called for every vertex and hyperarc added (not for ones that already existed).
  struct Observer {
    std::function<void(VertexId, const TaskElement&)> onVertex;
    std::function<void(HyperarcId, const TaskArc&)> onHyperarc;
  };

  /// Adds what the task space allows and is not in the graph yet (closure from the start elements).
  void build(const TaskSpace& space, const TaskReachability& reach, const Observer& observer = {});

  const TaskGraph& graph() const { return graph_; }
  HyperarcId source() const { return source_; }
  HyperarcId sink() const { return sink_; }
  /// The vertex of an element, if present.
  std::optional<VertexId> find(const TaskElement& e) const { return graph_.find(e); }
  std::string label(VertexId v, const TaskSpace& space) const;
  std::string label(HyperarcId a, const TaskSpace& space) const;

 private:
  VertexId addVertex(const TaskElement& e, const Observer& observer);
  void addArc(std::vector<VertexId> tail, std::vector<VertexId> head, const TaskArc& arc,
              const Observer& observer);
  void closeObject(const TaskSpace& space, const TaskReachability& reach, int object,
                   const Observer& observer);
  void addInspections(const TaskSpace& space, const TaskReachability& reach, const Observer& observer);

  TaskGraph graph_;
  HyperarcId source_;
  HyperarcId sink_;
};

/// Human-readable element label: "ur5e_0", "ur5e_0+obj_3(top)", "obj_3@goal", "inspect#0 done".
std::string elementLabel(const TaskElement& e, const TaskSpace& space);

}  // namespace dash
