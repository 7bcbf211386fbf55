#pragma once
// Motion constraints C_M = (Pi_1, Pi_2, p) of Lazy-DaSH (paper, "Query (Motion-extended Hypergraph)"
// and "Motion Conflict Resolution and Constraint Feedback"): the histories that lead to the motions in
// conflict and the region p where they conflict. A history is named by its robot and its last element
// (the task step it ends with) and matched by the robot's own transition history up to that step (the
// task hyperarcs it took part in), so a constraint applies to any task plan in which that robot got
// there the same way. Pi_1 is the constrained history: the motion query and conflict resolution plan
// its move into that step with the region to avoid (MotionContext::avoid). The region is
//  - world boxes (`region`): what was in the way when conflict resolution could not separate two motions
//    (the other robot's parts over the conflict's time window, or the resting object), grown by the
//    planner's clearance; the move is replanned around them;
//  - transition configurations (`configurations`): a move the motion query found no way to, or a
//    handover conflict resolution could not schedule; other configurations of the same transition are
//    sampled outside it;
//  - a time window alone (a contact the validator found between the scheduler's check instants):
//    conflict resolution checks those instants from then on.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/collision/collision_world.h"
#include "engine/robots/joint_vector.h"
#include "engine/scene/scene.h"
#include "engine/task/task_plan.h"

// In namespace dash::lazy: DaSH has motion constraints of its own (engine/dash/motion_constraint.h).
namespace dash::lazy {

struct MotionConstraint {
  struct History {
    int robot = -1;
    int step = -1;                      ///< the task step the robot's history ends with (-1: its way home)
    std::vector<std::uint32_t> arcs;    ///< the robot's task hyperarcs up to that step (historyOf)
    /// The transition configuration the history ends at, when known: a constraint learned for one
    /// transition sample is lifted when another is drawn (paper, "Theoretical Properties").
    JointVector q;
  };
  std::vector<History> histories;                            ///< Pi_1, the constrained one (and Pi_2)
  std::vector<Aabb> region;                                  ///< region p: world boxes to stay out of
  int object = -1;                                           ///< the resting object in the way, if any
  std::vector<std::pair<int, JointVector>> configurations;   ///< region p: (robot, configuration)
  double t_begin = -1.0, t_end = -1.0;                       ///< the conflict's time window, seconds
  std::string cause;

  bool hasTimeRegion() const { return t_begin >= 0.0; }
  /// "ur5e_0 at step 3 (ur5e_1 at step 2); region: 9 boxes in [x0, x1] x [y0, y1] x [z0, z1] m; t in
  /// [1.250, 1.500] s; boxes: [x0 y0 z0 x1 y1 z1] ..." (the constraint event's content; the boxes last,
  /// each min and max corner in metres, 0.1 mm).
  std::string describe(const Scene& scene) const;
};

/// Robot `robot`'s transition history in `plan` up to and including step `step`: the task hyperarcs
/// of the steps it takes part in (every step when step < 0: its way home).
MotionConstraint::History historyOf(const TaskPlan& plan, int robot, int step);

/// The motion constraints of a run, in the order they were learned.
class MotionConstraintSet {
 public:
  /// Adds c, in force; returns its index (the constraint event's id).
  std::uint32_t add(MotionConstraint c) {
    constraints_.push_back(std::move(c));
    in_force_.push_back(true);
    return static_cast<std::uint32_t>(constraints_.size() - 1);
  }
  const std::vector<MotionConstraint>& all() const { return constraints_; }
  std::size_t size() const { return constraints_.size(); }
  bool inForce(std::size_t id) const { return in_force_[id]; }
  /// Whether a constraint in force with the same constrained history (Pi_1) and the same region boxes is known.
  bool contains(const MotionConstraint& c) const;
  /// The region boxes of every constraint in force whose constrained history (Pi_1) is robot `robot`'s
  /// history up to step `step` of `plan`, ending at transition configuration q: what its move into
  /// that step keeps out of.
  std::vector<Aabb> regionsFor(const TaskPlan& plan, int robot, int step, const JointVector& q) const;
  /// Lifts the constraints whose regions regionsFor() returns (the move found no way around them);
  /// returns their indices.
  std::vector<std::size_t> liftRegionsFor(const TaskPlan& plan, int robot, int step, const JointVector& q);
  /// Lifts every constraint in force (a restart: new samples); returns their indices.
  std::vector<std::size_t> liftAll();

 private:
  /// The indices of the constraints in force with a region that regionsFor() matches.
  std::vector<std::size_t> regionIndicesFor(const TaskPlan& plan, int robot, int step, const JointVector& q) const;

  std::vector<MotionConstraint> constraints_;  ///< every one learned, lifted ones kept for the record
  std::vector<bool> in_force_;                 ///< per constraint
};

}  // namespace dash::lazy
