#pragma once
// A fully validated roadmap for one robot in one hand state: DaSH's motion planner, PRM (Kavraki et
// al. 1996) through OMPL's og::PRM, every milestone and edge checked before any query (paper,
// "Method Descriptions": "motion feasibility is all validated during the H_M construction phase").
//
// og::PRM samples and connects milestones for the robot with an empty hand against what never moves
// (self collisions and obstacles). A planning space is the robot holding a given object geometry with
// a given grasp X_TO (or nothing): "one roadmap per robot per hand state" is shared by all of them,
// and each space keeps its own graph of the milestones and edges that stay valid with that held
// geometry, validated eagerly when the space is first used (objects of the same size held with the
// same X_TO share one space: the geometry is identical). Anchors are the transition configurations
// of the motion hypergraph, connected to their nearest vertices of the space by validated edges.
//
// Resting objects and other robots change during a plan and are not part of the roadmap: plan()
// searches a space for a path that also avoids them (CBS-MP's low-level search under constraints),
// checking only the edges its shortest paths use, as conflict resolution asks for it.
#include <cstddef>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_state.h"
#include "engine/core/deadline.h"
#include "engine/motion/motion_context.h"

namespace ompl::geometric {
class PRM;
}
namespace ompl::base {
class SpaceInformation;
}

namespace dash {

class StaticRobotValidity;

struct ValidatedRoadmapParams {
  unsigned int neighbours = 10;         ///< og::PRM k nearest
  unsigned int anchor_neighbours = 12;  ///< vertices an anchor tries to connect to
};

class ValidatedRoadmap {
 public:
  /// Shortest paths from one vertex of a space: distance and predecessor per vertex (-1: none).
  struct Tree {
    std::vector<double> dist;
    std::vector<int> pred;
  };

  ValidatedRoadmap(const CollisionWorld& world, CollisionContext& context, int robot,
                   ValidatedRoadmapParams params = {});
  ~ValidatedRoadmap();
  ValidatedRoadmap(const ValidatedRoadmap&) = delete;
  ValidatedRoadmap& operator=(const ValidatedRoadmap&) = delete;

  int robot() const { return robot_; }
  /// Grows og::PRM until it holds `milestones` milestones (or the deadline), then validates what is
  /// new in every space already in use.
  void growTo(std::size_t milestones, const Deadline& deadline);
  std::size_t milestoneCount() const;

  /// The planning space for `held` (an empty hand when held.object < 0), created and validated on
  /// first use. Returns its index.
  int space(const HeldObject& held);
  /// Adds q (valid in space s: the caller checked it) as an anchor, connected by validated edges to
  /// its nearest vertices; the same q twice gives the same vertex.
  int anchor(int s, const JointVector& q);
  const JointVector& config(int s, int vertex) const;
  Tree shortestPaths(int s, int from) const;
  /// The path of `tree` from its root to `to` (empty if unreachable).
  std::vector<JointVector> pathTo(int s, const Tree& tree, int to) const;

  /// A path a -> b in `context` (held object, resting objects, parked robots): the straight segment
  /// if it is free, else shortest paths of the space whose edges are checked against the context,
  /// invalid ones removed, until one is free (Lazy-PRM's loop, over a validated roadmap).
  std::optional<std::vector<JointVector>> plan(const JointVector& a, const JointVector& b,
                                               const MotionContext& context, const Deadline& deadline);

  /// Vertices and edges summed over the spaces in use (anchors included).
  std::size_t vertexCount() const;
  std::size_t edgeCount() const;
  std::size_t spaceCount() const { return spaces_.size(); }

 private:
  struct Space;
  void sync(Space& space);
  void connectAnchor(Space& space, int vertex, bool to_anchors_only);
  bool segmentFree(const Space& space, const JointVector& a, const JointVector& b);
  bool stateFree(const Space& space, const JointVector& q);

  const CollisionWorld* world_;
  CollisionContext* context_;
  int robot_;
  int dof_;
  ValidatedRoadmapParams params_;
  std::shared_ptr<StaticRobotValidity> statically_;  ///< og::PRM's validity, and each space's with its held geometry
  std::shared_ptr<ompl::base::SpaceInformation> si_;
  std::shared_ptr<ompl::geometric::PRM> prm_;
  std::vector<std::unique_ptr<Space>> spaces_;
};

}  // namespace dash
