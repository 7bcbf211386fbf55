#pragma once
// Internal to engine/tpg: the graph builder (buildGraph, tpg.h). tpg_build.cpp orders the events,
// cuts each arm's timeline into pieces and merges them into the graph's nodes; tpg_build_edges.cpp
// finds the pairs of pieces that meet and the edges they need (indexed by time and swept box,
// tpg_index.h, so a piece is tested only against pieces that can come near it).
#include <chrono>
#include <cstddef>
#include <functional>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "engine/tpg/tpg.h"
#include "engine/tpg/tpg_index.h"
#include "engine/tpg/tpg_sweep.h"

namespace dash::tpg::detail {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }
constexpr double kTimeTolerance = 1e-6;  ///< s: as the validator's, events this close share an instant
constexpr int kMaxRounds = 60;

/// An object resting at one place from one event (or the start) to another (or the end).
struct Rest {
  int object = -1;
  Pose X_WO = Pose::Identity();
  int from = -1;  ///< sorted event position that put it there; -1: the scene's start
  int to = -1;    ///< sorted event position that takes it away; -1: it stays
};

/// A node of one arm while building: a piece (piece >= 0) or an event (event position >= 0).
struct Slot {
  int piece = -1;
  int event = -1;  ///< position in the sorted events
};

/// A pair of pieces (arm, t0, t1 each): the key of meetCached's verdicts, kept across rounds.
struct MeetKey {
  int arm_a;
  double a0, a1;
  int arm_b;
  double b0, b1;
  bool operator==(const MeetKey&) const = default;
};
struct MeetKeyHash {
  std::size_t operator()(const MeetKey& k) const {
    std::size_t h = std::hash<int>()(k.arm_a * 4099 + k.arm_b);
    for (double d : {k.a0, k.a1, k.b0, k.b1}) h = h * 1000003u ^ std::hash<double>()(d);
    return h;
  }
};

class Builder {
 public:
  Builder(const Scene& scene, const Plan& plan, const BuildOptions& options)
      : scene_(scene), plan_(plan), options_(options), sweeps_(scene, options) {}

  Graph build(BuildStats* stats);

 private:
  void sortEvents();
  void replayHolders();
  void initialCuts();
  void makePieces();
  bool findConflicts();
  void indexArms();
  void reportPair(int a, int b);
  bool orderOverlapping(int a, int b);
  /// Swept edges from the pieces of arm `from` that end before a piece of arm `to` starts.
  void addPredecessors(int from, int to);
  void syncHandovers();
  /// For a piece of `to` starting at t, how many of `from`'s pieces handovers (directly or through
  /// other arms) already order before it (sync_); `cursor` walks to's syncs and `bound` from's pieces.
  int handoverBound(int from, int to, double t, std::size_t& cursor, int& bound) const;
  /// Whether the pieces meet: for pieces the plan runs at once, at distance 0 (a handover's gripper
  /// and the object may touch); for the others, within the clearance.
  bool meetCached(int a, int b, bool overlap);
  Sweeps::Thresholds touching() const;
  bool sequential(const Piece& first, const Piece& then);
  void addObjectEdges();
  void addHandoverEdges();
  Graph mergeAndReduce() const;
  int slotBefore(int arm, int event_position) const;
  int eventArm(int position) const { return arm_of_robot_.at(plan_.events[at(order_[at(position)])].robot); }
  double eventTime(int position) const { return plan_.events[at(order_[at(position)])].t; }
  Pose tcp(int arm, double t) const;
  void addEdge(int from_arm, int from_slot, int to_arm, int to_slot, Edge::Why why);
  /// sweeps_.prepare, kept across cutting rounds (a piece not cut again is the same piece).
  void prepareCached(Piece& piece);

  const Scene& scene_;
  const Plan& plan_;
  BuildOptions options_;
  Sweeps sweeps_;
  std::map<std::string, int> arm_of_robot_;
  std::vector<int> scene_robot_;       ///< per arm
  std::vector<int> order_;             ///< event indices in the validator's order
  std::vector<int> position_of_event_;  ///< inverse of order_
  std::vector<Rest> rests_;
  std::vector<std::pair<int, int>> handovers_;  ///< (event position, the other holder's arm)
  std::vector<std::set<double>> cuts_;          ///< per arm
  std::vector<Piece> pieces_;
  std::vector<std::vector<Slot>> slots_;        ///< per arm, in order
  std::vector<std::pair<int, int>> slot_of_piece_;  ///< (arm, slot)
  std::vector<int> slot_of_event_;              ///< per event position: slot index on its arm
  std::set<std::tuple<int, int, int, int, int>> edges_;  ///< (from arm, from slot, to arm, to slot, why)
  /// A handover instant of an arm and its vector clock just after: per arm c, the latest time t such
  /// that c's pieces ending by t run before the arm's pieces that start from this instant.
  struct Sync {
    double t = 0.0;
    std::vector<double> clock;
  };
  std::vector<std::vector<Sync>> sync_;  ///< per arm, in time order
  std::vector<std::vector<int>> of_arm_;        ///< per arm: its pieces, in time order
  std::vector<BoxIndex> index_;                 ///< per arm: its pieces' boxes (of_arm_ order)
  std::vector<Aabb> arm_box_;                   ///< per arm: all its pieces' boxes
  std::unordered_map<MeetKey, bool, MeetKeyHash> meet_cache_;
  std::map<std::tuple<int, double, double>, Piece> prepared_;  ///< (arm, t0, t1) -> prepared piece
  std::vector<std::pair<int, double>> pending_;  ///< cuts asked for in this round: (arm, t)
  int forced_ = 0;
  bool last_round_ = false;  ///< no more cuts: overlapping pairs that meet are ordered by start (forced)
  int rounds_ = 0;
  int max_pieces_ = 0;
  std::chrono::steady_clock::time_point last_report_ = std::chrono::steady_clock::now();
  long long ordered_tests_ = 0, ordered_meet_ = 0;  ///< pairs the plan runs one after the other: tested, met
};

}  // namespace dash::tpg::detail
