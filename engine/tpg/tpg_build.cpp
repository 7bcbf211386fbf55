// buildGraph (tpg.h): events in the validator's order, each arm's timeline cut into pieces, the
// pairs of pieces that meet, cuts made finer where two pieces overlap in time, then the pieces merged
// into segments between the cuts that edges need.
#include <algorithm>
#include <limits>
#include <map>
#include <set>
#include <tuple>

#include "engine/core/check.h"
#include "engine/robots/kinematics.h"
#include "engine/tpg/tpg.h"
#include "engine/tpg/tpg_sweep.h"

namespace dash::tpg {

namespace {

using detail::Piece;
using detail::Sweeps;

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
  bool orderOverlapping(int a, int b);
  void addPredecessors(const std::vector<int>& from, const std::vector<int>& to);
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
  std::map<std::tuple<int, double, double, int, double, double>, bool> meet_cache_;
  std::map<std::tuple<int, double, double>, Piece> prepared_;  ///< (arm, t0, t1) -> prepared piece
  std::vector<std::pair<int, double>> pending_;  ///< cuts asked for in this round: (arm, t)
  int forced_ = 0;
  bool last_round_ = false;  ///< no more cuts: overlapping pairs that meet are ordered by start (forced)
  int rounds_ = 0;
  int max_pieces_ = 0;
};

Pose Builder::tcp(int arm, double t) const {
  const SceneRobot& robot = scene_.robots[at(scene_robot_[at(arm)])];
  return forwardKinematics(*robot.model, robot.X_WB, plan_.robots[at(arm)].positionAt(t)).X_WT;
}

void Builder::sortEvents() {
  // The validator's order at one instant: grasps of an object another robot holds, releases, other
  // grasps, inspects. Which grasps take over a held object follows from replaying in time order.
  std::vector<int> by_time(plan_.events.size());
  for (std::size_t i = 0; i < by_time.size(); ++i) by_time[i] = static_cast<int>(i);
  std::stable_sort(by_time.begin(), by_time.end(),
                   [&](int a, int b) { return plan_.events[at(a)].t < plan_.events[at(b)].t; });
  std::map<std::string, int> holders;
  std::size_t i = 0;
  while (i < by_time.size()) {
    std::size_t j = i;
    const double t = plan_.events[at(by_time[i])].t;
    while (j < by_time.size() && plan_.events[at(by_time[j])].t - t <= kTimeTolerance) ++j;
    std::vector<std::pair<int, int>> ranked;  // (rank, event)
    for (std::size_t k = i; k < j; ++k) {
      const PlanEvent& e = plan_.events[at(by_time[k])];
      int rank = 3;
      if (e.type == PlanEvent::Type::kGrasp) rank = holders[e.object] > 0 ? 0 : 2;
      if (e.type == PlanEvent::Type::kRelease) rank = 1;
      ranked.emplace_back(rank, by_time[k]);
    }
    std::stable_sort(ranked.begin(), ranked.end(), [](auto& a, auto& b) { return a.first < b.first; });
    for (const auto& [rank, e] : ranked) {
      order_.push_back(e);
      const PlanEvent& ev = plan_.events[at(e)];
      if (ev.type == PlanEvent::Type::kGrasp) ++holders[ev.object];
      if (ev.type == PlanEvent::Type::kRelease) --holders[ev.object];
    }
    i = j;
  }
  position_of_event_.assign(order_.size(), -1);
  for (std::size_t p = 0; p < order_.size(); ++p) position_of_event_[at(order_[p])] = static_cast<int>(p);
}

void Builder::replayHolders() {
  const int objects = static_cast<int>(scene_.objects.size());
  std::vector<std::vector<std::pair<int, Pose>>> holders(at(objects));  // (arm, X_TO)
  std::vector<int> open(at(objects), -1);                                // rest in rests_
  for (int o = 0; o < objects; ++o) {
    open[at(o)] = static_cast<int>(rests_.size());
    rests_.push_back({o, scene_.objects[at(o)].X_WO_start, -1, -1});
  }
  for (int p = 0; p < static_cast<int>(order_.size()); ++p) {
    const PlanEvent& e = plan_.events[at(order_[at(p)])];
    if (e.type == PlanEvent::Type::kInspect) continue;
    const int o = scene_.objectIndex(e.object);
    DASH_THROW_UNLESS(o >= 0, "event of unknown object \"" + e.object + "\": validate the plan first");
    const int arm = eventArm(p);
    auto& hs = holders[at(o)];
    if (e.type == PlanEvent::Type::kGrasp) {
      if (!hs.empty()) handovers_.emplace_back(p, hs.front().first);
      if (open[at(o)] >= 0) rests_[at(open[at(o)])].to = p;
      open[at(o)] = -1;
      hs.emplace_back(arm, e.X_TO);
    } else {
      auto it = std::find_if(hs.begin(), hs.end(), [&](const auto& h) { return h.first == arm; });
      DASH_THROW_UNLESS(it != hs.end(), e.robot + " releases " + e.object + " it does not hold: validate the plan first");
      const Pose X_WO = tcp(arm, e.t) * it->second;
      hs.erase(it);
      if (!hs.empty()) {
        handovers_.emplace_back(p, hs.front().first);
      } else {
        open[at(o)] = static_cast<int>(rests_.size());
        rests_.push_back({o, X_WO, p, -1});
      }
    }
  }
}


void Builder::makePieces() {
  pieces_.clear();
  slots_.assign(plan_.robots.size(), {});
  slot_of_piece_.clear();
  slot_of_event_.assign(order_.size(), -1);
  for (int arm = 0; arm < static_cast<int>(plan_.robots.size()); ++arm) {
    const RobotTrajectory& traj = plan_.robots[at(arm)];
    std::vector<int> own;  // event positions of this arm, in order
    for (int p = 0; p < static_cast<int>(order_.size()); ++p) {
      if (eventArm(p) == arm) own.push_back(p);
    }
    std::vector<double> cuts;
    for (double t : cuts_[at(arm)]) {
      if (cuts.empty() || t - cuts.back() > kTimeTolerance) cuts.push_back(t);
      else if (t == *cuts_[at(arm)].rbegin()) cuts.back() = t;  // keep the end exactly
    }
    std::size_t next_event = 0;
    int held = -1;
    Pose X_TO = Pose::Identity();
    int last = -1;
    auto addEvents = [&](double until) {
      while (next_event < own.size() && eventTime(own[next_event]) <= until + kTimeTolerance) {
        const int p = own[next_event++];
        const PlanEvent& e = plan_.events[at(order_[at(p)])];
        if (e.type == PlanEvent::Type::kGrasp) {
          held = scene_.objectIndex(e.object);
          X_TO = e.X_TO;
          last = held;
        } else if (e.type == PlanEvent::Type::kRelease) {
          held = -1;
        }
        slot_of_event_[at(p)] = static_cast<int>(slots_[at(arm)].size());
        slots_[at(arm)].push_back({-1, p});
      }
    };
    for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
      addEvents(cuts[k]);
      Piece piece;
      piece.robot = scene_robot_[at(arm)];
      piece.arm = arm;
      piece.t0 = cuts[k];
      piece.t1 = cuts[k + 1];
      piece.q0 = traj.positionAt(piece.t0);
      piece.q1 = traj.positionAt(piece.t1);
      piece.held = held;
      piece.X_TO = X_TO;
      piece.adjacent_last = last;
      for (std::size_t n = next_event; n < own.size(); ++n) {
        const PlanEvent& e = plan_.events[at(order_[at(own[n])])];
        if (e.type != PlanEvent::Type::kGrasp) continue;
        piece.adjacent_next = scene_.objectIndex(e.object);
        break;
      }
      prepareCached(piece);
      slot_of_piece_.emplace_back(arm, static_cast<int>(slots_[at(arm)].size()));
      slots_[at(arm)].push_back({static_cast<int>(pieces_.size()), -1});
      pieces_.push_back(std::move(piece));
    }
    addEvents(std::numeric_limits<double>::infinity());
  }
  max_pieces_ = std::max(max_pieces_, static_cast<int>(pieces_.size()));
}

void Builder::prepareCached(Piece& piece) {
  const auto key = std::make_tuple(piece.arm, piece.t0, piece.t1);
  if (auto it = prepared_.find(key); it != prepared_.end()) {
    piece.moves = it->second.moves;
    piece.rate = it->second.rate;
    piece.box = it->second.box;
    return;
  }
  sweeps_.prepare(piece);
  prepared_.emplace(key, piece);
}

void Builder::addEdge(int from_arm, int from_slot, int to_arm, int to_slot, Edge::Why why) {
  if (from_arm == to_arm || from_slot < 0 || to_slot < 0) return;
  if (from_slot >= static_cast<int>(slots_[at(from_arm)].size()) || to_slot >= static_cast<int>(slots_[at(to_arm)].size())) return;
  edges_.insert({from_arm, from_slot, to_arm, to_slot, static_cast<int>(why)});
}

bool Builder::meetCached(int a, int b, bool overlap) {
  const Piece& pa = pieces_[at(a)];
  const Piece& pb = pieces_[at(b)];
  const auto key = std::make_tuple(pa.arm, pa.t0, pa.t1, pb.arm, pb.t0, pb.t1);
  if (auto it = meet_cache_.find(key); it != meet_cache_.end()) return it->second;
  const bool meet = overlap ? sweeps_.meet(pa, pb, touching(), options_.max_evaluations)
                            : sweeps_.meet(pa, pb, {options_.clearance, options_.clearance}, options_.max_ordered_evaluations);
  meet_cache_.emplace(key, meet);
  return meet;
}

Sweeps::Thresholds Builder::touching() const { return {0.0, -options_.contact_tolerance}; }

/// Running first, then waiting for it, is safe for `first` and `then`: first's sweep stays apart from
/// where `then` waits (its start), and then's sweep from where `first` stopped (its end).
bool Builder::sequential(const Piece& first, const Piece& then) {
  return !sweeps_.meet(first, sweeps_.stillAt(then, 0.0), touching(), options_.max_evaluations) &&
         !sweeps_.meet(then, sweeps_.stillAt(first, 1.0), touching(), options_.max_evaluations);
}

/// Orders one pair of pieces of two arms that the plan runs at once (their times overlap) and that may
/// meet; asks for finer cuts where neither order is proved safe (returns false then).
bool Builder::orderOverlapping(int a, int b) {
  const Piece& pa = pieces_[at(a)];
  const Piece& pb = pieces_[at(b)];
  if (pa.box.exteriorDistance(pb.box) > options_.clearance) return true;
  if (!meetCached(a, b, true)) return true;  // apart at 0 (a handover's contact may touch)
  const auto [arm_a, slot_a] = slot_of_piece_[at(a)];
  const auto [arm_b, slot_b] = slot_of_piece_[at(b)];
  auto contains = [](const Piece& h, const Piece& x) {
    return h.t0 <= x.t0 + kTimeTolerance && x.t1 <= h.t1 + kTimeTolerance;
  };
  // One holds still the whole time the other runs: the other runs between its arrival and departure.
  if (!pa.moves && contains(pa, pb)) {
    addEdge(arm_a, slot_a - 1, arm_b, slot_b, Edge::Why::kSwept);
    addEdge(arm_b, slot_b, arm_a, slot_a + 1, Edge::Why::kSwept);
    return true;
  }
  if (!pb.moves && contains(pb, pa)) {
    addEdge(arm_b, slot_b - 1, arm_a, slot_a, Edge::Why::kSwept);
    addEdge(arm_a, slot_a, arm_b, slot_b + 1, Edge::Why::kSwept);
    return true;
  }
  auto cutAt = [&](const Piece& p, double t) {
    if (t > p.t0 + kTimeTolerance && t < p.t1 - kTimeTolerance) pending_.emplace_back(p.arm, t);
  };
  const bool small = pa.rate <= options_.min_cut && pb.rate <= options_.min_cut;
  if (small || last_round_) {  // as fine as allowed: one after the other, if either order is safe
    const bool a_first = pa.t0 <= pb.t0;
    const Piece& first = a_first ? pa : pb;
    const Piece& then = a_first ? pb : pa;
    if (sequential(first, then)) {
      addEdge(first.arm, a_first ? slot_a : slot_b, then.arm, a_first ? slot_b : slot_a, Edge::Why::kSwept);
    } else if (sequential(then, first)) {
      addEdge(then.arm, a_first ? slot_b : slot_a, first.arm, a_first ? slot_a : slot_b, Edge::Why::kSwept);
    } else {
      ++forced_;
      addEdge(first.arm, a_first ? slot_a : slot_b, then.arm, a_first ? slot_b : slot_a, Edge::Why::kSwept);
    }
    return true;
  }
  if (!pa.moves || !pb.moves) {  // cut the mover where the holder arrives and leaves
    const Piece& holder = pa.moves ? pb : pa;
    const Piece& mover = pa.moves ? pa : pb;
    cutAt(mover, holder.t0);
    cutAt(mover, holder.t1);
    return false;
  }
  const Piece& longer = pa.rate >= pb.rate ? pa : pb;
  cutAt(longer, (longer.t0 + longer.t1) / 2);
  return false;
}

/// Swept edges into each piece of `to` from the pieces of `from` that end before it starts: only the
/// latest such piece that meets it (the earlier ones run before that one, so their edges would be
/// implied by the arm's order), and none at or before the piece an earlier target already waits for
/// (it runs before that target, which runs before this one). Prefix boxes stop the scan once nothing
/// earlier can come near.
void Builder::addPredecessors(const std::vector<int>& from, const std::vector<int>& to) {
  std::vector<Aabb> prefix(from.size());
  for (std::size_t k = 0; k < from.size(); ++k) {
    if (k > 0) prefix[k] = prefix[k - 1];
    prefix[k].extend(pieces_[at(from[k])].box);
  }
  const double c = options_.clearance;
  std::size_t before = 0;  // pieces of `from` that end before the target starts
  std::size_t implied = 0;  // pieces of `from` before this one precede an earlier target: implied
  for (int y : to) {
    const Piece& py = pieces_[at(y)];
    while (before < from.size() && pieces_[at(from[before])].t1 <= py.t0 + kTimeTolerance) ++before;
    for (std::size_t k = before; k-- > implied;) {
      if (prefix[k].exteriorDistance(py.box) > c) break;
      const int x = from[k];
      if (pieces_[at(x)].box.exteriorDistance(py.box) > c || !meetCached(x, y, false)) continue;
      const auto [arm_x, slot_x] = slot_of_piece_[at(x)];
      const auto [arm_y, slot_y] = slot_of_piece_[at(y)];
      addEdge(arm_x, slot_x, arm_y, slot_y, Edge::Why::kSwept);
      implied = k + 1;
      break;
    }
  }
}

bool Builder::findConflicts() {
  pending_.clear();
  edges_.clear();
  forced_ = 0;
  const int arms = static_cast<int>(plan_.robots.size());
  std::vector<std::vector<int>> of_arm(at(arms));
  std::vector<Aabb> arm_box(at(arms));
  for (int i = 0; i < static_cast<int>(pieces_.size()); ++i) {
    of_arm[at(pieces_[at(i)].arm)].push_back(i);
    arm_box[at(pieces_[at(i)].arm)].extend(pieces_[at(i)].box);
  }
  for (int a = 0; a < arms; ++a) {
    for (int b = a + 1; b < arms; ++b) {
      if (arm_box[at(a)].isEmpty() || arm_box[at(b)].isEmpty()) continue;
      if (arm_box[at(a)].exteriorDistance(arm_box[at(b)]) > options_.clearance) continue;
      // Pairs the plan runs at once (each arm's pieces are in time order: a sliding window).
      std::size_t first = 0;
      for (int i : of_arm[at(a)]) {
        const Piece& pa = pieces_[at(i)];
        while (first < of_arm[at(b)].size() && pieces_[at(of_arm[at(b)][first])].t1 <= pa.t0 + kTimeTolerance) ++first;
        for (std::size_t k = first; k < of_arm[at(b)].size(); ++k) {
          const int j = of_arm[at(b)][k];
          if (pieces_[at(j)].t0 >= pa.t1 - kTimeTolerance) break;
          orderOverlapping(i, j);
        }
      }
      addPredecessors(of_arm[at(a)], of_arm[at(b)]);
      addPredecessors(of_arm[at(b)], of_arm[at(a)]);
    }
  }
  if (pending_.empty()) return false;
  for (const auto& [arm, t] : pending_) cuts_[at(arm)].insert(t);
  return true;
}

void Builder::addObjectEdges() {
  for (int i = 0; i < static_cast<int>(pieces_.size()); ++i) {
    const Piece& p = pieces_[at(i)];
    const auto [arm, slot] = slot_of_piece_[at(i)];
    for (const Rest& rest : rests_) {
      if (!sweeps_.meetsObject(p, rest.object, rest.X_WO)) continue;
      const double from_t = rest.from < 0 ? -1.0 : eventTime(rest.from);
      const double to_t = rest.to < 0 ? std::numeric_limits<double>::infinity() : eventTime(rest.to);
      auto eventSlot = [&](int position) { return std::make_pair(eventArm(position), slot_of_event_[at(position)]); };
      if (rest.from >= 0 && p.t1 <= from_t + kTimeTolerance) {
        const auto [ea, es] = eventSlot(rest.from);
        addEdge(arm, slot, ea, es, Edge::Why::kObject);
      } else if (rest.to >= 0 && p.t0 >= to_t - kTimeTolerance) {
        const auto [ea, es] = eventSlot(rest.to);
        addEdge(ea, es, arm, slot, Edge::Why::kObject);
      } else {
        if (rest.from >= 0) {
          const auto [ea, es] = eventSlot(rest.from);
          addEdge(ea, es, arm, slot, Edge::Why::kObject);
        }
        if (rest.to >= 0) {
          const auto [ea, es] = eventSlot(rest.to);
          addEdge(arm, slot, ea, es, Edge::Why::kObject);
        }
      }
    }
  }
}

/// The last slot of `arm` that comes before the event at `position` in the validator's order.
int Builder::slotBefore(int arm, int position) const {
  const double t = eventTime(position);
  int before = -1;
  const auto& slots = slots_[at(arm)];
  for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
    const Slot& slot = slots[at(s)];
    const bool earlier = slot.piece >= 0 ? pieces_[at(slot.piece)].t1 <= t + kTimeTolerance : slot.event < position;
    if (!earlier) break;
    before = s;
  }
  return before;
}

void Builder::addHandoverEdges() {
  for (const auto& [position, other] : handovers_) {
    const int arm = eventArm(position);
    const int slot = slot_of_event_[at(position)];
    const int before = slotBefore(other, position);
    addEdge(other, before, arm, slot, Edge::Why::kHandover);
    addEdge(arm, slot, other, before + 1, Edge::Why::kHandover);
  }
  // An inspect needs its lid away: after the lid's last event before it, before the lid's next one.
  for (int p = 0; p < static_cast<int>(order_.size()); ++p) {
    const PlanEvent& e = plan_.events[at(order_[at(p)])];
    if (e.type != PlanEvent::Type::kInspect || e.task < 0 || e.task >= static_cast<int>(scene_.tasks.size())) continue;
    const int lid = scene_.tasks[at(e.task)].requires_removed_object;
    if (lid < 0) continue;
    const std::string& lid_id = scene_.objects[at(lid)].id;
    int prev = -1, next = -1;
    for (int q = 0; q < static_cast<int>(order_.size()); ++q) {
      const PlanEvent& f = plan_.events[at(order_[at(q)])];
      if (f.type == PlanEvent::Type::kInspect || f.object != lid_id) continue;
      if (q < p) prev = q;
      if (q > p && next < 0) next = q;
    }
    if (prev >= 0) addEdge(eventArm(prev), slot_of_event_[at(prev)], eventArm(p), slot_of_event_[at(p)], Edge::Why::kObject);
    if (next >= 0) addEdge(eventArm(p), slot_of_event_[at(p)], eventArm(next), slot_of_event_[at(next)], Edge::Why::kObject);
  }
}

Graph Builder::mergeAndReduce() const {
  Graph g;
  g.clearance = options_.clearance;
  g.forced = forced_;
  const int arms = static_cast<int>(plan_.robots.size());
  std::set<std::pair<int, int>> outgoing, incoming;
  for (const auto& [fa, fs, ta, ts, why] : edges_) {
    outgoing.emplace(fa, fs);
    incoming.emplace(ta, ts);
  }
  std::vector<std::vector<int>> node_of_slot(at(arms));
  for (int arm = 0; arm < arms; ++arm) {
    g.robots.push_back(plan_.robots[at(arm)].robot);
    const auto& slots = slots_[at(arm)];
    for (int s = 0; s < static_cast<int>(slots.size()); ++s) {
      const Slot& slot = slots[at(s)];
      const bool joins = s > 0 && slot.piece >= 0 && slots[at(s - 1)].piece >= 0 && !outgoing.count({arm, s - 1}) &&
                         !incoming.count({arm, s});
      if (slot.event >= 0) {
        const double t = eventTime(slot.event);
        g.nodes.push_back({Node::Kind::kEvent, arm, t, t, order_[at(slot.event)], false});
      } else if (joins) {
        Node& last = g.nodes.back();
        last.t1 = pieces_[at(slot.piece)].t1;
        last.moves = last.moves || pieces_[at(slot.piece)].moves;
      } else {
        const Piece& p = pieces_[at(slot.piece)];
        g.nodes.push_back({Node::Kind::kMotion, arm, p.t0, p.t1, -1, p.moves});
      }
      node_of_slot[at(arm)].push_back(static_cast<int>(g.nodes.size()) - 1);
    }
  }
  // Lifted, then only the latest source per (target, source arm) and the earliest target per
  // (source, target arm): an arm runs its nodes in order, so the others are implied.
  std::map<std::pair<int, int>, std::pair<int, int>> latest;  // (to, from arm) -> (from, why)
  for (const auto& [fa, fs, ta, ts, why] : edges_) {
    const int from = node_of_slot[at(fa)][at(fs)];
    const int to = node_of_slot[at(ta)][at(ts)];
    auto [it, fresh] = latest.try_emplace({to, fa}, from, why);
    if (!fresh && (from > it->second.first || (from == it->second.first && why < it->second.second))) it->second = {from, why};
  }
  std::map<std::pair<int, int>, std::pair<int, int>> earliest;  // (from, to arm) -> (to, why)
  for (const auto& [key, value] : latest) {
    const int to = key.first;
    const int ta = g.nodes[at(to)].robot;
    auto [it, fresh] = earliest.try_emplace({value.first, ta}, to, value.second);
    if (!fresh && (to < it->second.first || (to == it->second.first && value.second < it->second.second))) {
      it->second = {to, value.second};
    }
  }
  for (const auto& [key, value] : earliest) g.edges.push_back({key.first, value.first, static_cast<Edge::Why>(value.second)});
  std::sort(g.edges.begin(), g.edges.end(), [](const Edge& a, const Edge& b) {
    return std::tie(a.to, a.from) < std::tie(b.to, b.from);
  });
  return g;
}

/// Each arm is cut at its points, at its events and at the events of the arms that can come near it
/// (their reach, the boxes of all their pieces, within the clearance): only those can bound an edge.
void Builder::initialCuts() {
  const double end = std::max(plan_.lastTime(), plan_.makespan);
  const int arms = static_cast<int>(plan_.robots.size());
  cuts_.assign(at(arms), {});
  for (int arm = 0; arm < arms; ++arm) {
    auto& cuts = cuts_[at(arm)];
    cuts.insert(0.0);
    cuts.insert(end);
    for (const TrajectoryPoint& p : plan_.robots[at(arm)].points) cuts.insert(std::min(p.t, end));
  }
  for (const PlanEvent& e : plan_.events) cuts_[at(arm_of_robot_.at(e.robot))].insert(std::min(e.t, end));
  makePieces();
  std::vector<Aabb> reach(at(arms));
  for (const Piece& p : pieces_) reach[at(p.arm)].extend(p.box);
  for (int arm = 0; arm < arms; ++arm) {
    for (const PlanEvent& e : plan_.events) {
      const int other = arm_of_robot_.at(e.robot);
      if (other != arm && reach[at(arm)].exteriorDistance(reach[at(other)]) <= options_.clearance) {
        cuts_[at(arm)].insert(std::min(e.t, end));
      }
    }
  }
}

Graph Builder::build(BuildStats* stats) {
  for (int arm = 0; arm < static_cast<int>(plan_.robots.size()); ++arm) {
    const std::string& id = plan_.robots[at(arm)].robot;
    const int r = scene_.robotIndex(id);
    DASH_THROW_UNLESS(r >= 0, "the plan's robot \"" + id + "\" is not in the scene");
    DASH_THROW_UNLESS(!plan_.robots[at(arm)].points.empty(), "robot \"" + id + "\" has no points");
    arm_of_robot_[id] = arm;
    scene_robot_.push_back(r);
  }
  for (const PlanEvent& e : plan_.events) {
    DASH_THROW_UNLESS(arm_of_robot_.count(e.robot), "an event names robot \"" + e.robot + "\", which the plan lacks");
  }
  sortEvents();
  replayHolders();
  initialCuts();
  for (;;) {
    makePieces();
    ++rounds_;
    last_round_ = rounds_ >= kMaxRounds;
    const bool again = findConflicts();
    if (options_.progress) {
      options_.progress("round " + std::to_string(rounds_) + ": " + std::to_string(pieces_.size()) + " pieces, " +
                        std::to_string(meet_cache_.size()) + " pairs tested, " + std::to_string(sweeps_.evaluations()) +
                        " distance evaluations, " + std::to_string(pending_.size()) + " cuts asked");
    }
    if (!again) break;
  }
  addObjectEdges();
  addHandoverEdges();
  Graph g = mergeAndReduce();
  if (stats != nullptr) {
    stats->pieces = max_pieces_;
    stats->evaluations = static_cast<int>(sweeps_.evaluations());
    stats->rounds = rounds_;
  }
  return g;
}

}  // namespace

Graph buildGraph(const Scene& scene, const Plan& plan, const BuildOptions& options, BuildStats* stats) {
  DASH_THROW_UNLESS(options.clearance >= 0.0 && options.clearance <= 0.1, "clearance must be within 0 .. 0.1 m");
  DASH_THROW_UNLESS(options.resolution > 0.0 && options.resolution <= 0.01, "resolution must be within 0 .. 0.01 m");
  DASH_THROW_UNLESS(options.contact_floor > 0.0 && options.contact_floor <= options.resolution,
                    "contact_floor must be within 0 .. resolution");
  DASH_THROW_UNLESS(options.contact_tolerance >= 0.0 && options.contact_tolerance <= 1e-4,
                    "contact_tolerance must be within 0 .. 1e-4 m");
  DASH_THROW_UNLESS(options.min_cut > 0.0 && options.max_evaluations > 0 && options.max_ordered_evaluations > 0,
                    "min_cut, max_evaluations and max_ordered_evaluations must be positive");
  Builder builder(scene, plan, options);
  return builder.build(stats);
}

}  // namespace dash::tpg
