#pragma once
// Internal to MotionLayer: the motion hypergraph H_M of one task plan as the motion query reads it
// (paper, "Motion Planning Layer"). motion_construction.cpp builds it before the query: per robot and
// task step, the motion vertices at the transition configurations task conflict detection chose, the
// approach start and retreat end around each (anchors), and the move hyperarcs between them whose paths
// are not yet validated. motion_query.cpp searches it along the task plan, validates lazily, and grows
// it when a move fails (farther anchors: local refinement; then global sampling).
#include <optional>
#include <vector>

#include "engine/hypergraph/hypergraph.h"
#include "engine/motion/motion_context.h"
#include "engine/motion/motion_layer.h"

namespace dash {

/// One robot's part in one task step (or its way home): where it must get to and the alternatives
/// H_M holds for its ends.
struct VisitAnchors {
  StepVisit visit;    ///< step, receiver, q, held_before/after; q_pre/q_post are set from the choice
  int robot = -1;
  bool home = false;  ///< the robot's way home (no transition: pre = {home})
  /// This robot's previous visit (index into MotionAnchors::visits), -1: it starts at home.
  int previous = -1;
  bool is_giver = false;
  /// The retreat backs off along the robot's own approach axis (so may back off farther).
  bool own_axis = true;
  /// Approach starts, [0] as constructed; local refinement may add a farther one.
  std::vector<JointVector> pre;
  /// Retreat ends, [0] as constructed; local refinement may add a farther one.
  std::vector<JointVector> post;
  std::vector<VertexId> pre_vertex, post_vertex;
  VertexId at_q;     ///< the robot at q before the transition
  VertexId after_q;  ///< the robot at q after it
  MotionContext context;  ///< of the transit and approach
};

struct MotionAnchors {
  std::vector<ObjectLayout> layouts;  ///< resting objects before each step, and at the end
  /// Schedule order: per step its participants (the giver before the receiver), then the ways home.
  std::vector<VisitAnchors> visits;
  /// Per step: its transition hyperarc and the indices of its visits.
  std::vector<HyperarcId> transition;
  std::vector<std::vector<int>> step_visits;
  std::vector<VertexId> home;  ///< per robot
  HyperarcId source;
  /// Where the objects and tasks end (the sink's tail besides the robots, whose ends the query chooses).
  std::vector<VertexId> end_items;
};

}  // namespace dash
