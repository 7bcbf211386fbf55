#pragma once
// The motion planning layer of Lazy-DaSH (paper, "Motion Planning Layer"). Representation construction
// first: the motion hypergraph H_M for the task space elements of the current task plan, anchored at
// the transition configurations task conflict detection already sampled, its moves not yet validated
// (motion_construction.cpp). Then the motion query (motion_query.cpp): a search over H_M guided by the
// task plan that validates lazily in schedule order, against the objects resting at that point of the
// schedule (straight segment first, then the robot's edge-unvalidated roadmap), grows H_M where a move
// fails and backtracks. The result is an optimistic schedule: each robot's motions are collision-free in
// its own composition space; other robots are ignored until conflict resolution.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/events/event_emitter.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/motion/motion_constraints.h"
#include "engine/motion/motion_hypergraph.h"
#include "engine/motion/planning_spaces.h"
#include "engine/task/task_conflict_detection.h"
#include "engine/task/task_plan.h"

namespace dash {

/// One robot's part in one task step: get there, do the transition, back off.
struct StepVisit {
  int step = -1;
  bool receiver = false;               ///< handover receiver (else the actor / giver)
  std::vector<JointVector> transit;    ///< from where the robot was to q_pre (first = previous end)
  JointVector q_pre;                   ///< approach start
  JointVector q;                       ///< the transition configuration
  JointVector q_post;                  ///< retreat end
  /// q_pre -> q and q -> q_post: the TCP's straight line as waypoints (cartesian_path.h), so that a
  /// held object comes down onto (and lifts off) its support without dipping into it. {q} alone when
  /// the robot does not back off. Timed, checked and written to the plan point by point.
  std::vector<JointVector> approach;
  std::vector<JointVector> retreat;
  HeldObject held_before;              ///< during transit and approach
  HeldObject held_after;               ///< during retreat
};

/// v.approach (and v.q_pre) from a back-off path of v.q (v.q first, the approach start last), or v.q
/// alone when there is none.
void setApproach(StepVisit& v, const std::optional<std::vector<JointVector>>& back_off);
/// v.retreat (and v.q_post) from a back-off path of v.q (v.q first, the retreat end last), or v.q alone.
void setRetreat(StepVisit& v, const std::optional<std::vector<JointVector>>& back_off);

struct RobotMotionPlan {
  std::vector<StepVisit> visits;
  std::vector<JointVector> home_path;  ///< from the last retreat back home (empty if none needed)
};

struct MotionLayerParams {
  double approach_distance = 0.06;  ///< metres the TCP backs off along its approach axis
  double side_lift = 0.015;         ///< metres a sideways back-off also rises
  /// Farther back-offs, when no transit reaches the short ones (a shelf cubby): the farthest valid
  /// one is used (ascending list).
  std::vector<double> deep_approach_distances = {0.15, 0.2, 0.25, 0.3, 0.35};
  bool straight_first = true;   ///< the straight segment before a roadmap query (beyond the paper)
  bool global_sampling = true;  ///< RRT-Connect when the roadmap finds no way between valid ends
  RoadmapParams roadmap;
};

/// "ur5e_0+obj_2 (top)", "obj_2@1": a motion vertex's task element, for event labels.
std::string motionVertexLabel(const Scene& scene, const lazy::MotionVertex& v);

enum class MotionStatus { kOk, kFailed, kTimeout };

struct MotionLayerResult {
  MotionStatus status = MotionStatus::kFailed;
  std::vector<RobotMotionPlan> robots;  ///< one per scene robot
  int failed_step = -1;                 ///< the step whose motion could not be found
  /// At failed_step: the robot that found no way, and the transition configuration it was going to.
  /// `ends_free`: both ends of the missing move were collision-free (the roadmap found no way between
  /// them), so another configuration for the same transition may do.
  int failed_robot = -1;
  JointVector failed_q;
  bool ends_free = false;
  std::string reason;
  /// Hyperarcs of the hyperpath the motion query found in H_M (source and sink included; 0 when it
  /// found none). The query's H_ME holds at least these, and also the branches it backtracked from.
  std::size_t hyperpath_hyperarcs = 0;
  /// Moves the query expanded and found invalid (dead branches of H_ME), and backtracks to a robot's
  /// previous visit (its retreat left for a farther one stays in H_ME too). H_ME of this query holds
  /// exactly hyperpath_hyperarcs + failed_moves + backtracks hyperarcs when it reached the sink.
  std::size_t failed_moves = 0;
  std::size_t backtracks = 0;
};

struct MotionAnchors;  // motion_anchors.h

class MotionLayer {
 public:
  MotionLayer(const CollisionWorld& world, CollisionContext& context, log::EventEmitter& emitter,
              MotionLayerParams params = {});

  MotionLayerResult plan(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                         const TaskSpace& space, const Deadline& deadline);
  /// From now on every move into a task step keeps out of the regions of the motion constraints on its
  /// history (nullptr: none). The set must outlive the layer's use of it.
  void respect(const lazy::MotionConstraintSet* constraints) { constraints_ = constraints; }

  /// Multiplies the roadmap query budgets (existing roadmaps and those created later).
  void scaleBudget(double factor);
  std::size_t roadmapVertices() const;
  std::size_t roadmapEdges() const;
  /// Per planning space (robot, empty hand or holding): that roadmap's sizes (0 when never built).
  std::size_t roadmapVertices(int robot, bool holding) const;
  std::size_t roadmapEdges(int robot, bool holding) const;
  /// H_M as it stands (live sizes) and H_ME summed over every motion query of the run.
  const lazy::MotionHypergraph& hypergraph() const { return graph_; }
  std::size_t motionVertices() const { return graph_.vertexCount(); }
  std::size_t motionHyperarcs() const { return graph_.hyperarcCount(); }
  std::size_t extendedVertices() const { return graph_.extendedVertexCount(); }
  std::size_t extendedHyperarcs() const { return graph_.extendedHyperarcCount(); }
  /// Over every motion query of the run: how often a query backtracked to a robot's previous visit.
  std::int64_t queryBacktracks() const { return query_backtracks_; }
  /// Over every motion query of the run: moves expanded and found invalid.
  std::int64_t queryFailedMoves() const { return query_failed_moves_; }

  /// Whether robot `robot`'s move into task step `step` (its visit in `motions`) starts or ends inside
  /// `region`: the start of its transit (the previous retreat's end) or its approach start (the
  /// transition's back-off). Both are fixed, so no replanned move can keep out of such a region. False
  /// when `motions` has no such visit.
  bool fixedEndsEnter(const MotionLayerResult& motions, int robot, int step, const std::vector<Aabb>& region) const;

  /// A path from -> to in `context`: the straight segment if it is free, else a roadmap query.
  std::optional<std::vector<JointVector>> connect(int robot, const JointVector& from, const JointVector& to,
                                                  const MotionContext& context, const Deadline& deadline);

 private:
  friend struct MotionConstruction;  // motion_construction.cpp: H_M for a task plan, before the query
  friend struct MotionQuery;         // motion_query.cpp: the search over H_M along the task plan
  /// The end of a missing move that is in collision ("start", "approach start", "transition") and
  /// with what; empty when all three are free.
  std::string collidingEnd(int robot, const JointVector& from, const JointVector& q_pre, const JointVector& q,
                           const HeldObject& held, const ObjectLayout& layout) const;
  /// The end of a move (start, approach start) inside the region of a motion constraint, or empty.
  std::string endInRegion(int robot, const JointVector& from, const JointVector& q_pre, const MotionContext& context) const;
  /// ": the <end> configuration is in collision (...)", or that the roadmap found no way between valid ends.
  static std::string whyNoPath(const std::string& colliding_end);
  /// q moved so that the TCP goes back along its own approach axis (or along `direction_W`, a world
  /// direction, when given) by the approach distance, on a straight line (backOffPath, on the IK branch
  /// of q) whose waypoints and segments are all free. A handover partner standing still at its
  /// transition configuration must also stay clear of it; when it is in the way of the sideways rise,
  /// the straight back-off is tried.
  std::optional<JointVector> backedOff(int robot, const JointVector& q, const HeldObject& held,
                                       const ObjectLayout& layout, const std::optional<Vec3>& direction_W = {},
                                       double distance = 0.0, const std::optional<RobotState>& partner = {});
  /// v.approach and v.retreat (cartesian_path.h's backOffPath) for the ends v.q_pre, v.q, v.q_post of
  /// robot `robot`'s visit: the paths backedOff checked.
  void setBackOffPaths(StepVisit& v, int robot) const;
  /// Whether the back-off path (q first) is free: its waypoints and segments, an empty gripper out of
  /// the contact boxes of the objects it does not grasp, the standing partner (if any) clear of it.
  bool backOffFree(int robot, const std::vector<JointVector>& path, const HeldObject& held, const ObjectLayout& layout,
                   const std::optional<RobotState>& partner) const;
  /// The farthest of the deep approach distances q can back off by (backedOff), if any.
  std::optional<JointVector> farthestBackOff(int robot, const JointVector& q, const HeldObject& held,
                                             const ObjectLayout& layout);
  /// Representation construction: H_M for the task plan's elements (motion_construction.cpp).
  MotionAnchors construct(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions, const TaskSpace& space);
  /// The motion query over what construct() built, growing it where a move fails (motion_query.cpp).
  MotionLayerResult query(MotionAnchors& anchors, const TaskPlan& plan, const TaskSpace& space, const Deadline& deadline);
  LazyRoadmap& roadmap(int robot, bool holding);

  const CollisionWorld* world_;
  CollisionContext* context_;
  log::EventEmitter* emitter_;
  MotionLayerParams params_;
  PerPlanningSpace<LazyRoadmap> roadmaps_;
  const lazy::MotionConstraintSet* constraints_ = nullptr;
  lazy::MotionHypergraph graph_;
  std::int64_t query_backtracks_ = 0;
  std::int64_t query_failed_moves_ = 0;
};

}  // namespace dash
