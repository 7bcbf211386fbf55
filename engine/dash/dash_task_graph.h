#pragma once
// DaSH's task space hypergraph H_T (Motes et al., T-RO 2023; the Lazy-DaSH paper, "Representation
// Construction (Task Space Hypergraph)": "the object-only task space elements differ from those in
// DaSH"). Object-only elements are location-free: O_j stands for the object resting anywhere under
// its stability constraint, so there is one O_j per object (TaskElement::objectAt(j, -1)) instead of
// one per location. Robots alone R_i and robots holding an object with a grasp class R_i+O_j(g) are
// as in Lazy-DaSH. Hyperarcs: pick {R_i, O_j} -> {R_i+O_j(g)} when robot i can grasp object j with
// class g at one of its placements (start, goal, pre-sampled), place (the reverse), handover
// {R_i+O_j(g1), R_k} -> {R_i, R_k+O_j(g2)} for arms in range with compatible classes, and inspect.
// Where each object rests is decided in the motion hypergraph, which DaSH queries directly.
#include <functional>
#include <span>
#include <string>

#include "engine/hypergraph/hypergraph.h"
#include "engine/task/reachability.h"
#include "engine/task/task_arc.h"
#include "engine/task/task_element.h"
#include "engine/task/task_space.h"

namespace dash {

using DashTaskGraph = Hypergraph<TaskElement, TaskArc>;

struct DashTaskGraphObserver {
  std::function<void(VertexId, const TaskElement&)> onVertex;
  /// With the hyperarc's tail and head (valid during the call).
  std::function<void(HyperarcId, const TaskArc&, std::span<const VertexId> tail, std::span<const VertexId> head)>
      onHyperarc;
};

/// Builds H_T for `space` (its locations are the placements the reachability test looks at).
DashTaskGraph buildDashTaskGraph(const TaskSpace& space, const TaskReachability& reach,
                                 const DashTaskGraphObserver& observer = {});

/// "ur5e_0", "ur5e_0+obj_3(top)", "obj_3", "inspect#0 done".
std::string dashElementLabel(const TaskElement& e, const Scene& scene);

}  // namespace dash
