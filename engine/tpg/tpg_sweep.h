#pragma once
// Internal to engine/tpg: whether two motion pieces' swept volumes (or a piece's and a resting
// object's box) come within the clearance, certified the validator's way (certified_geometry.h):
// over a box of fractions (u of piece a, v of piece b) the distance measured at its centre, less the
// farthest any part can move from there (the per-body motion bounds of segment_queries.h times the
// half-widths), bounds the distance over the whole box. Boxes that this does not prove apart are
// split, down to `resolution` of motion; what is left meets (conservatively: within clearance plus
// resolution). Distances are exact FCL distances between the robots' bodies and held objects;
// bounding spheres skip pairs that cannot matter. A handover's gripper and the object the other arm
// holds touch by design (the contact pair): the validator lets them touch but not overlap, and
// measures them every certify_floor of motion rather than proving them apart (a touching pair cannot
// be proved apart). meet() does the same: a box that only the contact pair keeps open is split down
// to `contact_floor` and meets only where a distance measured at its centre or one of its corners
// (where a replay holds an arm at a piece's end) is below the contact threshold.
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/tpg/tpg.h"

namespace dash::tpg::detail {

/// One straight joint-space piece of one arm, holding one object (or none) throughout.
struct Piece {
  int robot = -1;   ///< scene robot index
  int arm = -1;     ///< Plan::robots index
  double t0 = 0.0, t1 = 0.0;
  JointVector q0, q1;
  int held = -1;    ///< object index, -1: empty hand
  Pose X_TO = Pose::Identity();
  int adjacent_last = -1;  ///< the object the arm held last before the piece (its gripper may touch it)
  int adjacent_next = -1;  ///< the object it holds next after the piece
  bool moves = false;
  double rate = 0.0;       ///< m: the most any of its points moves over the whole piece
  Aabb box;                ///< holds every part at every pose of the piece
  std::vector<Aabb> parts; ///< per part (bodies, then the held object): holds it at every pose of the piece
};

/// Some part of `a` comes within `margin` of some part of `b` by their boxes (a cheap filter: pieces
/// whose arms' boxes overlap often have no two parts near each other).
bool partsNear(const Piece& a, const Piece& b, double margin);
/// Some part of `a` comes within `margin` of `box` by its box.
bool partsNear(const Piece& a, const Aabb& box, double margin);

class Sweeps {
 public:
  Sweeps(const Scene& scene, const BuildOptions& options);

  /// Fills piece.moves, rate, box and parts.
  void prepare(Piece& piece);
  /// Distances at or below which a pair counts as meeting: every pair but those below (`normal`), and
  /// a gripper with the object another robot holds, of a handover its arm is in (`contact`: they touch
  /// by design; -infinity leaves them out).
  struct Thresholds {
    double normal = 0.0;
    double contact = 0.0;
  };
  /// Some pair of the two pieces' parts comes within its threshold somewhere (or cannot be proved
  /// apart to `resolution` within `budget` distance evaluations).
  bool meet(const Piece& a, const Piece& b, Thresholds thresholds, long long budget);
  /// The box of `object` at X_WO.
  Aabb objectBox(int object, const Pose& X_WO) const { return boxAabb(X_WO, world_.object(object).half_extents); }
  /// The piece's parts come within the clearance of `object` resting at X_WO.
  bool meetsObject(const Piece& a, int object, const Pose& X_WO);
  /// The piece held still at fraction u (0: its start, 1: its end), prepared.
  Piece stillAt(const Piece& p, double u);
  long long evaluations() const { return evaluations_; }

 private:
  struct Part {
    const fcl::CollisionGeometry<double>* shape = nullptr;
    Pose X = Pose::Identity();
    Vec3 centre = Vec3::Zero();
    double radius = 0.0;
    bool gripper = false;
    bool held = false;
    int object = -1;
  };
  void pose(const Piece& p, double u, std::vector<Part>& out) const;
  /// Smallest distance between the parts, ordinary pairs and contact pairs apart (a lower bound
  /// where it is above `enough`).
  struct Distances {
    double normal;
    double contact;
  };
  Distances distance(const Piece& a, const std::vector<Part>& pa, const Piece& b, const std::vector<Part>& pb,
                     double enough);

  const Scene& scene_;
  BuildOptions options_;
  CollisionWorld world_;
  CollisionContext context_;
  std::vector<Part> scratch_a_, scratch_b_;
  long long evaluations_ = 0;
};

}  // namespace dash::tpg::detail
