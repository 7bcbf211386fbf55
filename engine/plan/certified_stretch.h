#pragma once
// Internal to certified_geometry.cpp: conservative advancement over one stretch between two
// consecutive point or event times (certified_geometry.h says what is checked and why it is sound).
#include <cstddef>
#include <deque>
#include <map>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_report.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/collision_world.h"
#include "engine/plan/plan_validator.h"
#include "engine/plan/validation_timeline.h"

namespace dash::validation {

/// A stretch of time over which one pair was closer than allowed (overlapping, or under the clearance).
struct PairContact {
  CollisionElement a;  ///< a robot body or a held object
  CollisionElement b;
  double t_first = 0.0;
  double t_last = 0.0;
  double distance = 0.0;  ///< smallest signed distance measured in the stretch
  double t_closest = 0.0;
  bool from_start = false;  ///< already in contact at the stretch's start
  bool to_end = false;      ///< still in contact at its end
  /// No measured instant was in contact: conservative advancement reached its floor without proving
  /// the pair apart (a possible contact). `bound` is the smallest distance the motion bound allows.
  bool possible = false;
  double bound = 0.0;
};

/// The smallest distance measured for one pair over the plan.
struct PairMinimum {
  CollisionElement a;
  CollisionElement b;
  bool contact_meant = false;
  double distance = 0.0;
  double t = 0.0;
};
using PairId = std::tuple<int, int, int, int, int, int, int, int>;
PairId pairId(const CollisionElement& a, const CollisionElement& b);
using PairMinima = std::map<PairId, PairMinimum>;
/// Keeps the smaller of each pair's minima (equal distances: the earlier), whatever the order of merging.
void mergeMinima(PairMinima& into, const PairMinima& from);

/// For each epoch and object held in it: the obstacles and objects it rests on where it is picked up
/// and where it is put down (within the contact tolerance of it at those poses). Empty otherwise.
using Supports = std::vector<std::vector<std::vector<CollisionElement>>>;
Supports findSupports(const CollisionWorld& world, CollisionContext& context, const Timeline& timeline);

struct Stretch {
  double t0 = 0.0;
  double t1 = 0.0;
  int epoch = 0;
  /// Robots whose parts meet anything only as they did at the end of the previous stretch (they hold
  /// still and the epoch is the same) need no check; false for the first stretch and after events.
  bool same_epoch_as_before = false;
};

/// One checker per thread; the world, motion, timeline and supports are shared read-only.
class StretchChecker {
 public:
  StretchChecker(const CollisionWorld& world, const PlanMotion& motion, const Timeline& timeline,
                 const Supports& supports, const ValidationOptions& options);

  /// Walks every pair of `stretch`, appending contacts and lowering minima.
  void check(const Stretch& stretch, std::vector<PairContact>& contacts, PairMinima& minima);
  std::size_t evaluations() const { return evaluations_; }

 private:
  /// One robot's parts at fraction u of the stretch.
  struct Posed {
    std::vector<Pose> frames;
    std::vector<Pose> X_WG;     ///< each body's shape pose
    std::vector<Aabb> boxes;    ///< each body's world box, then the held object's
    Pose X_WO = Pose::Identity();  ///< held object
  };
  struct Robot {
    JointVector q0, q1;
    HeldObject held;
    bool moving = false;
    bool checked = false;          ///< moving, or the epoch changed
    std::vector<double> rate;      ///< per body, then the held object: bound per unit of u
    std::vector<Aabb> swept;       ///< per body, then the held object
    Aabb swept_all;
  };
  /// Side b of a pair: a static thing or another robot's part.
  struct Pair {
    int ra = -1, pa = -1;  ///< robot and part (body index, or bodies.size() for the held object)
    CollisionElement b;
    int rb = -1, pb = -1;  ///< for a robot part
    bool contact_meant = false;
    double rate = 0.0;
  };

  void setUp(const Stretch& stretch);
  const Posed& pose(int r, double u);
  void collectPairs(int r);
  void collectRobotPairs(int r, int s);
  void addPair(int ra, int pa, const CollisionElement& b, const Aabb& b_box, int rb, int pb, bool contact_meant);
  bool isSupport(int object, const CollisionElement& thing) const;
  /// `object` is the last one robot r held before the stretch's epoch or the next one it holds after
  /// it: r is about to grasp it (or take it over), or has let it go and not held anything since. Per
  /// robot, not per epoch: with many robots, other robots' events cut a back-off into many epochs.
  bool holdsAdjacent(int r, int object) const;
  struct GraspTarget {
    int last = -1;  ///< object the robot held most recently before the epoch
    int next = -1;  ///< object it holds next after the epoch
  };
  void findGraspTargets();
  std::vector<std::vector<GraspTarget>> grasp_targets_;  ///< per epoch, per robot
  /// Signed distance of the pair at u (exact = true), or, while the boxes are more than kBoxStepMargin
  /// beyond the clearance apart, their distance (a lower bound).
  double distance(const Pair& pair, double u, bool& exact);
  void advance(const Pair& pair, std::vector<PairContact>& contacts, PairMinima& minima);
  CollisionElement element(int r, int part) const;

  const CollisionWorld& world_;
  const PlanMotion& motion_;
  const Timeline& timeline_;
  const Supports& supports_;
  const ValidationOptions& options_;
  CollisionContext context_;
  Stretch stretch_;
  std::vector<Robot> robots_;
  /// One robot's poses in the current stretch, by u (a deque: references stay valid as it grows).
  struct Poses {
    std::unordered_map<double, std::size_t> index;
    std::deque<Posed> pool;
    std::size_t used = 0;
  };
  std::vector<Poses> poses_;
  std::vector<Pair> pairs_;
  std::size_t evaluations_ = 0;
};

}  // namespace dash::validation
