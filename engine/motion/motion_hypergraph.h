#pragma once
// The motion hypergraph H_M of Lazy-DaSH (paper, "Motion Planning Layer: Representation Construction"),
// kept for the whole run. A motion vertex is <v_T, q>: a task space element (robot alone, robot holding
// an object with a grasp class, object at a location) with an explicit configuration (joint values, or
// the object's pose). A motion hyperarc is <Tail, Head, E_T, pi>:
//   move        one robot in one composition space, tail {robot@q_a} head {robot@q_b}, path pi
//   pick/place  tail {robot@q, object@pose} -> head {robot+object@q} (and back for a place)
//   handover    ONE hyperarc coupling both robots: tail {giver+object@q, receiver@q2},
//               head {giver@q, receiver+object@q2}
//   inspect     tail {robot@q, task pending} -> head {robot@q, task done}
//   source/sink the start frontier (every robot home, every object at its start) and the end frontier.
// Elements are deduplicated across rounds (Hypergraph looks them up by property, tail and head): a
// transition configuration that a later task plan reuses is the same vertex, a move between the same
// two vertices the same hyperarc, so H_M grows only when a task plan needs an element it lacks. Sizes
// are the live structure's. The path of a move is the last one validated for it.
//
// The motion query (paper, "Query (Motion-extended Hypergraph)", motion_query.cpp) searches H_M guided by
// the task plan and validates lazily: it takes a hyperarc once its motion is validated. Its workspace is
// H_ME: each hyperarc taken is one extended hyperarc, the instances of its head new extended vertices;
// branches the query backtracks from stay in the workspace and in the counts.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "engine/geometry/pose.h"
#include "engine/hypergraph/hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"
#include "engine/events/event_emitter.h"
#include "engine/robots/joint_vector.h"
#include "engine/task/task_arc.h"
#include "engine/task/task_element.h"

// In namespace dash::lazy: DaSH has a motion hypergraph of its own (engine/dash/motion_hypergraph.h).
namespace dash::lazy {

/// <v_T, q>: robot >= 0 for a robot's configuration (values = joints), -1 for an object's pose
/// (values = translation, then the rotation matrix column by column) or a task's state (no values).
struct MotionVertex {
  std::int16_t robot = -1;
  TaskElement element;
  std::vector<double> values;

  bool operator==(const MotionVertex&) const = default;
};

enum class MotionArcType : std::int8_t { kSource, kSink, kMove, kTransition };

/// The property of a motion hyperarc: its kind and, for transitions, the task action E_T.
struct MotionArc {
  MotionArcType type = MotionArcType::kMove;
  TaskArc action;  ///< transitions only (default otherwise)

  bool operator==(const MotionArc& o) const { return type == o.type && action == o.action; }
};

}  // namespace dash::lazy

template <>
struct std::hash<dash::lazy::MotionVertex> {
  std::size_t operator()(const dash::lazy::MotionVertex& v) const noexcept;
};
template <>
struct std::hash<dash::lazy::MotionArc> {
  std::size_t operator()(const dash::lazy::MotionArc& a) const noexcept {
    return std::hash<dash::TaskArc>{}(a.action) * 31 + static_cast<std::size_t>(a.type);
  }
};

namespace dash::lazy {

/// What one motion query over H_M built (its extended hypergraph) and whether it reached the sink.
struct MotionQueryCounts {
  std::size_t extended_vertices = 0;
  std::size_t extended_hyperarcs = 0;
  bool reached_sink = false;
};

/// An instance of a motion vertex in a query's workspace (H_ME).
using ExtendedMotionVertex = std::uint32_t;

class MotionHypergraph {
 public:
  using Graph = Hypergraph<MotionVertex, MotionArc>;

  /// `emitter` receives an H_M event for each element actually added, and the H_ME events of each
  /// query; `labels` names robots and objects in those events (may be empty).
  explicit MotionHypergraph(log::EventEmitter& emitter, std::function<std::string(const MotionVertex&)> labels = {});

  VertexId robotVertex(int robot, const TaskElement& element, const JointVector& q);
  VertexId objectVertex(int object, int location, const Pose& X_WO);
  /// A task's state (pending or done: the lab's inspections), with no configuration.
  VertexId taskVertex(int task, bool done);
  /// A move of one robot; `path` (from -> to) is stored as the arc's pi. Empty when from == to (no arc).
  /// A path not `validated` (construction's stand-in) is stored only on a new arc: an arc H_M already
  /// holds keeps the path last validated for it.
  std::optional<HyperarcId> move(VertexId from, VertexId to, const std::vector<JointVector>& path,
                                 bool validated = true);
  HyperarcId transition(const TaskArc& action, std::vector<VertexId> tail, std::vector<VertexId> head);
  HyperarcId source(std::vector<VertexId> head);
  HyperarcId sink(std::vector<VertexId> tail);

  /// The path of a move, once the query validated one (H_M keeps the last validated path).
  void setPath(HyperarcId move, const std::vector<JointVector>& path) { paths_[move.value()] = path; }

  /// A new motion query's workspace (H_ME): nothing taken yet.
  void beginQuery();
  /// The query takes `arc` (validated): one extended hyperarc consuming the current instance of each
  /// tail vertex (created for a vertex the branch has not reached: the source's tail is empty), and a
  /// new instance of each head vertex. Returns the extended hyperarc's id within the run.
  std::uint32_t take(HyperarcId arc);
  /// The current query's counts.
  const MotionQueryCounts& queryCounts() const { return query_; }

  const Graph& graph() const { return graph_; }
  std::size_t vertexCount() const { return graph_.vertexCount(); }
  std::size_t hyperarcCount() const { return graph_.hyperarcCount(); }
  /// Over every query of the run.
  std::size_t extendedVertexCount() const { return extended_vertices_; }
  std::size_t extendedHyperarcCount() const { return extended_hyperarcs_; }
  const std::vector<JointVector>& path(HyperarcId move) const { return paths_[move.value()]; }
  /// Transition hyperarcs whose tail holds vertices of two different robots (handovers).
  std::size_t coupledHyperarcCount() const;

 private:
  VertexId addVertex(MotionVertex v);
  HyperarcId addArc(std::vector<VertexId> tail, std::vector<VertexId> head, MotionArc property, const char* type);

  log::EventEmitter* emitter_;
  std::function<std::string(const MotionVertex&)> labels_;
  Graph graph_;
  std::vector<std::vector<JointVector>> paths_;  ///< per hyperarc (moves only)
  std::size_t extended_vertices_ = 0;
  std::size_t extended_hyperarcs_ = 0;
  MotionQueryCounts query_;
  /// Per H_M vertex, its latest instance in the current query's workspace (absent: not reached).
  std::unordered_map<std::uint32_t, ExtendedMotionVertex> instance_;
  ExtendedMotionVertex newInstance(VertexId v);
  ExtendedMotionVertex instanceOf(VertexId v);
};

}  // namespace dash::lazy
