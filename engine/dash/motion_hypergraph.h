#pragma once
// DaSH's motion hypergraph H_M, built exhaustively before any query (paper, "Comparison with DaSH":
// DaSH "exhaustively adds every feasible transition and motion for each robot, object, and their
// interactions into the representation"). A motion vertex is a task space element with an explicit
// configuration: a robot alone at a configuration, a robot holding an object with a grasp X_TO at a
// configuration, an object resting at a placement, or a task state. Hyperarcs:
//  - transition (pick, place, handover, inspect): one per sampled transition configuration (the
//    catalog), its path the approach and retreat along the TCP axis;
//  - move: within one planning space (a robot alone, or a robot holding one object with one grasp),
//    from every configuration a transition leaves the robot at to every configuration a transition
//    needs it at, its path the shortest path in that space's validated roadmap, its cost the path
//    length; and back, from a configuration only a handover needs the robot at (waiting to give or
//    to receive) to home (empty hand) or to where the robot took the object (holding), so a robot
//    whose partner does not come can leave;
//  - source and sink: the start (robots at home, objects at their start) and the goal (objects at
//    their goal, robots at home, tasks done).
// Costs of transitions are their approach and retreat lengths; they are what the combined query sums.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/dash/transition_catalog.h"
#include "engine/dash/validated_roadmap.h"
#include "engine/hypergraph/hypergraph.h"
#include "engine/events/event_emitter.h"
#include "engine/motion/planning_spaces.h"

namespace dash {

struct MotionVertex {
  enum class Kind : std::int8_t { kSource, kSink, kRobot, kHolding, kObject, kTaskPending, kTaskDone };
  Kind kind = Kind::kRobot;
  std::int16_t robot = -1;
  std::int16_t object = -1;
  std::int16_t placement = -1;  ///< kObject: location index in the TaskSpace
  std::int16_t task = -1;
  std::int32_t config = -1;  ///< kRobot, kHolding: index into the configuration table
  std::int32_t grasp = -1;   ///< kHolding: index into the grasp (X_TO) table
  bool operator==(const MotionVertex&) const = default;
};

struct MotionArc {
  enum class Type : std::int8_t { kSource, kSink, kMove, kPick, kPlace, kHandover, kInspect };
  Type type = Type::kMove;
  std::int32_t index = -1;  ///< into moves / grasps / handovers / inspects of the catalog
  std::int32_t extra = -1;  ///< kInspect: the lid's placement (-1 when the task needs none)
  bool operator==(const MotionArc&) const = default;
};
const char* motionArcTypeName(MotionArc::Type t);

}  // namespace dash

template <>
struct std::hash<dash::MotionVertex> {
  std::size_t operator()(const dash::MotionVertex& v) const noexcept {
    std::uint64_t k = static_cast<std::uint8_t>(v.kind);
    for (std::int32_t x : {std::int32_t{v.robot}, std::int32_t{v.object}, std::int32_t{v.placement},
                           std::int32_t{v.task}, v.config, v.grasp})
      k = k * 1000003u + static_cast<std::uint32_t>(x);
    return std::hash<std::uint64_t>{}(k);
  }
};
template <>
struct std::hash<dash::MotionArc> {
  std::size_t operator()(const dash::MotionArc& a) const noexcept {
    const std::uint64_t k = (static_cast<std::uint64_t>(static_cast<std::uint8_t>(a.type)) << 56) ^
                            (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a.index)) << 20) ^
                            static_cast<std::uint32_t>(a.extra);
    return std::hash<std::uint64_t>{}(k);
  }
};

namespace dash {

using MotionGraph = Hypergraph<MotionVertex, MotionArc>;

/// A move hyperarc's motion.
struct MovePath {
  int robot = -1;
  HeldObject held;
  VertexId from;
  VertexId to;
  std::vector<JointVector> path;
  double length = 0.0;
  bool back = false;  ///< from a handover's waiting configuration back (home, or where the object was taken)
};

/// The validated roadmap of every planning space (robot, hand state).
using RoadmapSet = PerPlanningSpace<ValidatedRoadmap>;

class MotionHypergraph {
 public:
  /// Builds the vertices and the transition, source and sink hyperarcs for the catalog (kept by
  /// reference: it must outlive this object). Move hyperarcs come with connectMoves().
  MotionHypergraph(const TaskSpace& space, const TransitionCatalog& catalog, log::EventEmitter& emitter);

  /// Adds (or, after roadmaps grew, updates) the move hyperarcs of every planning space of the robots
  /// in `robots` (all robots when empty), from the roadmaps.
  void connectMoves(RoadmapSet& roadmaps, const std::vector<int>& robots, const Deadline& deadline);

  const MotionGraph& graph() const { return graph_; }
  HyperarcId source() const { return source_; }
  HyperarcId sink() const { return sink_; }
  double cost(HyperarcId a) const { return cost_[a.value()]; }
  const JointVector& config(int index) const { return configs_[index]; }
  const Pose& grasp(int index) const { return grasps_[index]; }
  const MovePath& move(int index) const { return moves_[index]; }
  const TransitionCatalog& catalog() const { return *catalog_; }
  const TaskSpace& space() const { return *space_; }
  VertexId homeVertex(int robot) const { return home_[robot]; }
  /// The transition hyperarcs a vertex is in the tail of (what a robot arriving there can do).
  const std::vector<HyperarcId>& transitionsFrom(VertexId v) const { return transitions_from_[v.value()]; }
  /// Shared placements (placement_sampling.h): the spot an object vertex rests at (-1 for a start or
  /// goal, an object's own) and the object vertices at one spot.
  int spotOf(VertexId v) const { return spot_of_[v.value()]; }
  const std::vector<VertexId>& spotVertices(int spot) const { return spot_vertices_[spot]; }
  /// The robot whose planning space a move hyperarc lies in.
  int moveRobot(HyperarcId a) const { return moves_[graph_.property(a).index].robot; }
  /// The vertex of `object` resting at location `placement` of the TaskSpace (invalid if none).
  VertexId objectVertex(int object, int placement) const;
  std::string label(VertexId v) const;
  std::string label(HyperarcId a) const;

 private:
  struct Space {
    int robot = -1;
    HeldObject held;
    std::vector<VertexId> entries;  ///< where transitions (or the start) leave the robot
    std::vector<VertexId> exits;    ///< where transitions (or the goal) need it
  };
  VertexId vertex(const MotionVertex& v);
  HyperarcId arc(std::vector<VertexId> tail, std::vector<VertexId> head, const MotionArc& a, double cost);
  int configIndex(int robot, const JointVector& q);
  int graspIndex(const Pose& X_TO);
  VertexId robotVertex(int robot, const JointVector& q);
  VertexId holdingVertex(int robot, const HeldObject& held, const JointVector& q);
  Space& space(int robot, const HeldObject& held);
  VertexId restingVertex(int object, int placement);  ///< objectVertex(), added if new
  VertexId taskVertex(int task, bool done);
  // The constructor's steps (H_M before any move).
  void addSourceAndSink();
  void addObjectVertices(std::vector<VertexId>& start, std::vector<VertexId>& goal);
  void addGraspArcs();
  void addHandoverArcs();
  void addInspectArcs();

  const TaskSpace* space_;
  const TransitionCatalog* catalog_;
  log::EventEmitter* emitter_;
  MotionGraph graph_;
  HyperarcId source_, sink_;
  std::vector<double> cost_;
  std::vector<JointVector> configs_;
  std::map<std::pair<int, std::vector<double>>, int> config_index_;
  std::vector<Pose> grasps_;
  std::vector<VertexId> home_;
  std::vector<Space> spaces_;
  std::vector<MovePath> moves_;
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> move_of_;  ///< (from, to) -> moves_ index
  std::vector<std::vector<HyperarcId>> transitions_from_;
  std::vector<int> spot_of_;
  std::vector<std::vector<VertexId>> spot_vertices_;
};

}  // namespace dash
