#pragma once
// Estimated cost-to-go over H_T for the greedy task query (paper: distance-based estimates,
// base-to-object for grasps and base-to-base for handovers, after Shome et al.). Each object's states
// (at a location, or held with a grasp class) form a small graph; a backward Dijkstra from the
// object's goal gives its cost-to-go. Robots alone cost nothing.
#include <functional>
#include <vector>

#include "engine/task/task_hypergraph.h"

namespace dash {

class TaskHeuristic {
 public:
  /// Hyperarcs that `forbidden` rejects (interaction constraints) are left out of the routes.
  TaskHeuristic(const TaskHypergraph& graph, const TaskSpace& space,
                const std::function<bool(HyperarcId)>& forbidden = {});

  /// Cost from v to the object's goal (any location if it has none); 0 for robots and tasks done.
  double costToGo(VertexId v) const { return to_goal_[v.value()]; }
  /// Cost from v to any location other than the object's start (for objects a pending task needs
  /// out of the way, such as a container lid); equals costToGo for other vertices.
  double costAway(VertexId v) const { return away_[v.value()]; }
  /// The object-state vertices an object-moving hyperarc leaves and reaches (pick, place, handover).
  struct ObjectMove {
    VertexId from;
    VertexId to;
    bool valid = false;
  };
  ObjectMove objectMove(HyperarcId a) const { return moves_[a.value()]; }

  static constexpr double kUnreachable = 1e9;

 private:
  std::vector<double> to_goal_;
  std::vector<double> away_;
  std::vector<ObjectMove> moves_;
};

}  // namespace dash
