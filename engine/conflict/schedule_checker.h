#pragma once
// Motion conflict detection in continuous time (paper, "Motion Conflicts"): a new timed piece of one
// robot against everything already scheduled — hyperarc-hyperarc conflicts with other robots' motions
// and hyperarc-vertex conflicts with resting objects. Each pair is checked on its own cuts: the robot
// against the resting objects is cut where its timeline or the object layout changes, the robot against
// another robot where either timeline has a breakpoint; inside each piece the pair moves linearly (and
// the resting objects are fixed), and the piece is checked at the collision checker's segment resolution.
//
// The pairs are independent: with several lanes (CheckPool, issue 38 item 3) each lane checks its own
// pairs' pieces in time order first, then the caller walks all pieces in the one-lane order and takes
// the first conflict, checking there whatever no lane did. The answer is the one-lane answer, for any
// number of lanes.
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <unordered_map>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/conflict/check_pool.h"
#include "engine/conflict/segment_boxes.h"
#include "engine/conflict/timeline.h"

namespace dash {

struct ScheduleConflict {
  double t = 0.0;   ///< start of the sub-interval where it was found
  int other = -1;   ///< the other robot, or -1 for a resting object / obstacle
  int object = -1;  ///< the resting object, if that was it
  int robot = -1;   ///< the robot whose motion was checked (-1: a resting object was checked)
};

class ScheduleChecker {
 public:
  /// `threads`: lanes of the checks (checkLanes: 0 is the hardware's, at most 2).
  ScheduleChecker(const CollisionWorld& world, CollisionContext& context, int threads = 1);

  /// Robot `robot` following `timeline` over [from, until] (until may be kForever: then up to the
  /// end of everything scheduled), against the other timelines and the resting objects.
  std::optional<ScheduleConflict> check(const RobotTimeline& timeline, double from, double until,
                                        const std::vector<RobotTimeline>& others, const ObjectTimeline& objects);
  /// Object `object` resting at X_WO from `from` on, against every robot timeline but `except`.
  std::optional<ScheduleConflict> checkResting(int object, const Pose& X_WO, double from,
                                               const std::vector<RobotTimeline>& timelines, int except);
  /// From now on every check also cuts time at t, so the robots' configurations at exactly t are checked
  /// (a contact the plan validator found there, between the instants this checker sampled).
  void alsoCheckAt(double t);
  /// Robot-pair pieces skipped so far because their swept boxes are apart (SegmentBoxes), and those
  /// handed to the exact check.
  std::uint64_t piecesApart() const { return pieces_apart_; }
  std::uint64_t piecesChecked() const { return pieces_checked_; }
  std::size_t lanes() const { return pool_.lanes(); }

 private:
  bool mayInteract(int a, int b) const { return interact_[a][b]; }
  /// The instants in [from, until] where `timeline`, `other` (if any) or `objects` (if any) change,
  /// with alsoCheckAt's, sorted and without repeats.
  void cutsOf(const RobotTimeline& timeline, const RobotTimeline* other, const ObjectTimeline* objects, double from,
              double until, std::vector<double>& cuts) const;

  const CollisionWorld* world_;
  CollisionContext* context_;
  ObjectLayout none_;  ///< no resting objects: the layout of robot-pair checks
  std::vector<std::vector<bool>> interact_;  ///< robots whose reach boxes (grown for a held object) meet
  std::vector<double> extra_cuts_;           ///< alsoCheckAt's instants, sorted
  /// A robot standing still (configuration, what it holds) against one straight segment of another
  /// robot's timeline (its ends, what it holds): free over the whole segment means free on every piece
  /// of it. Retiming a step checks the same waits and the same standing at the transition against the
  /// same segments of the others again and again; the verdicts are looked up here instead (a segment in
  /// conflict somewhere has its pieces checked one by one). Exact keys (no hash-only match).
  struct StillKey {
    std::vector<double> values;
    bool operator==(const StillKey& other) const { return values == other.values; }
  };
  struct StillKeyHash {
    std::size_t operator()(const StillKey& key) const;
  };
  /// The verdict of one piece and what it cost, kept until check's walk takes it: the walk adds the
  /// cost to the run's counters and the standing-still verdict to the shared ones, as one lane would
  /// have (a verdict the walk already holds costs nothing), so the counters do not depend on the lanes.
  struct PieceRecord {
    std::optional<ScheduleConflict> conflict;
    CollisionCounters cost;  ///< of the whole piece, a standing-still verdict computed for it included
    bool apart = false;      ///< a robot-pair piece skipped: the swept boxes are apart
    bool exact = false;      ///< a robot-pair piece handed to the exact check
    bool standing_computed = false;  ///< a standing-still verdict was computed for it (not found)
    StillKey standing_key;
    bool standing_free = false;
    CollisionCounters standing_cost;
  };
  struct PairPieces {                        ///< check's workspace: one pair's pieces
    const RobotTimeline* other = nullptr;    ///< null: the resting objects
    std::vector<double> cuts;
    std::size_t next = 0;                    ///< the next piece to check starts at cuts[next]
    std::size_t checked = 0;                 ///< pieces a lane checked from the first (see check)
    std::vector<PieceRecord> records;  ///< theirs, in order
  };
  std::vector<PairPieces> pairs_;

  /// What one lane checks with: its collision context (lane 0: the checker's) and its index of the
  /// scheduled pieces' boxes. The standing-still verdicts are shared: read by the lanes, written by
  /// check's walk alone, in the one-lane order.
  struct Lane {
    Lane(const CollisionWorld& world, CollisionContext* shared);
    std::unique_ptr<CollisionContext> own;  ///< lanes above 0
    CollisionContext* context;
    SegmentBoxes boxes;
  };
  /// Piece `j` of `pair` (robot `timeline` against the pair's other part), checked in `lane`; the lane's
  /// counters are left as they were (the cost goes to `record`).
  void checkPiece(Lane& lane, const RobotTimeline& timeline, const PairPieces& pair, std::size_t j,
                  const ObjectTimeline& objects, PieceRecord& record);
  /// The walk's taking of a piece's record: its cost and standing-still verdict, as one lane.
  void commit(const PieceRecord& record);
  /// Lane `lane` of `lanes`: its pairs' pieces in time order, each pair up to its first conflict, until
  /// a piece starts after the earliest conflict any lane found.
  void scanLane(std::size_t lane, std::size_t lanes, const RobotTimeline& timeline, const ObjectTimeline& objects);
  /// Whether `self` standing still is free of `other`'s whole segment holding [u, v]: looked up, or
  /// computed in `lane` and put in `record`. False: check the piece itself.
  bool standingFreeOfSegment(Lane& lane, const RobotState& self, const RobotTimeline& other, double u, double v,
                             PieceRecord& record) const;
  /// Whether robot `timeline` over [u, v] and `other` over [u, v] have swept boxes that are apart.
  static bool piecesApart(Lane& lane, const RobotTimeline& timeline, const RobotTimeline& other, double u, double v);
  std::unordered_map<StillKey, bool, StillKeyHash> still_;
  std::uint64_t pieces_apart_ = 0, pieces_checked_ = 0;
  CheckPool pool_;
  std::vector<std::unique_ptr<Lane>> lanes_;
  std::atomic<double> earliest_{0.0};  ///< scanLane: the earliest conflict found so far
};

}  // namespace dash
