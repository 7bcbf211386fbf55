// The edges of the graph under construction (tpg_builder.h): pairs of pieces that meet, those the
// plan runs at once cut finer or ordered, those it runs one after the other ordered as it does (only
// where the arms' order and their handovers do not imply it already), objects at rest, handovers.
// Pieces are found through each arm's index of swept boxes (tpg_index.h): a piece is tested only
// against the pieces of other arms that can come within the clearance of it.
#include <algorithm>
#include <chrono>
#include <limits>

#include "engine/tpg/tpg_builder.h"

namespace dash::tpg::detail {

bool Builder::meetCached(int a, int b, bool overlap) {
  const Piece& pa = pieces_[at(a)];
  const Piece& pb = pieces_[at(b)];
  const MeetKey key{pa.arm, pa.t0, pa.t1, pb.arm, pb.t0, pb.t1};
  if (auto it = meet_cache_.find(key); it != meet_cache_.end()) return it->second;
  const bool meet = overlap ? sweeps_.meet(pa, pb, touching(), options_.max_evaluations)
                            : sweeps_.meet(pa, pb, {options_.clearance, options_.clearance}, options_.max_ordered_evaluations);
  meet_cache_.emplace(key, meet);
  if (!overlap) {
    ++ordered_tests_;
    ordered_meet_ += meet;
  }
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
  if (!partsNear(pa, pb, options_.clearance)) return true;
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

/// Swept edges into each piece of arm `to` from the pieces of arm `from` that end before it starts:
/// only the latest such piece that meets it (the earlier ones run before that one, so their edges
/// would be implied by the arm's order), and none at or before the piece an earlier target already
/// waits for (it runs before that target, which runs before this one) or that a handover between
/// the two arms already orders before it. Candidates come from `from`'s box index, latest first.
void Builder::addPredecessors(int from, int to) {
  const std::vector<int>& xs = of_arm_[at(from)];
  const double c = options_.clearance;
  std::size_t before = 0;  // pieces of `from` that end before the target starts
  int implied = 0;         // pieces of `from` before this one are ordered before the target already
  std::size_t cursor = 0;
  int bound = 0;
  for (int y : of_arm_[at(to)]) {
    const Piece& py = pieces_[at(y)];
    while (before < xs.size() && pieces_[at(xs[before])].t1 <= py.t0 + kTimeTolerance) ++before;
    implied = std::max(implied, handoverBound(from, to, py.t0, cursor, bound));
    for (int k = static_cast<int>(before); (k = index_[at(from)].latestNear(py.box, c, implied, k)) >= 0;) {
      const int x = xs[at(k)];
      if (!detail::partsNear(pieces_[at(x)], py, c) || !meetCached(x, y, false)) continue;
      const auto [arm_x, slot_x] = slot_of_piece_[at(x)];
      const auto [arm_y, slot_y] = slot_of_piece_[at(y)];
      addEdge(arm_x, slot_x, arm_y, slot_y, Edge::Why::kSwept);
      implied = k + 1;
      break;
    }
  }
}

/// A handover between two arms at T orders every piece of either that ends by T before every piece
/// of the other that starts from T (addHandoverEdges: through the event and the other arm's slot), and
/// a chain of handovers at increasing instants orders along the chain (syncHandovers).
int Builder::handoverBound(int from, int to, double t, std::size_t& cursor, int& bound) const {
  const std::vector<Sync>& syncs = sync_[at(to)];
  while (cursor < syncs.size() && syncs[cursor].t <= t + kTimeTolerance) ++cursor;
  if (cursor == 0) return 0;
  const double until = syncs[cursor - 1].clock[at(from)];
  const std::vector<int>& xs = of_arm_[at(from)];
  while (bound < static_cast<int>(xs.size()) && pieces_[at(xs[at(bound)])].t1 <= until + kTimeTolerance) ++bound;
  return bound;
}

/// A progress line at most every 10 s within a round (a large plan's first round takes a while).
void Builder::reportPair(int a, int b) {
  if (!options_.progress) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_report_ < std::chrono::seconds(10)) return;
  last_report_ = now;
  options_.progress("round " + std::to_string(rounds_) + ": arms " + std::to_string(a) + " and " + std::to_string(b) +
                    " done, " + std::to_string(meet_cache_.size()) + " pairs tested (" + std::to_string(ordered_tests_) +
                    " run one after the other, " + std::to_string(ordered_meet_) + " of them meet), " +
                    std::to_string(sweeps_.evaluations()) + " distance evaluations");
}

/// Each arm's pieces in time order, their box index and the box of them all.
void Builder::indexArms() {
  const int arms = static_cast<int>(plan_.robots.size());
  of_arm_.assign(at(arms), {});
  arm_box_.assign(at(arms), Aabb());
  for (int i = 0; i < static_cast<int>(pieces_.size()); ++i) {
    of_arm_[at(pieces_[at(i)].arm)].push_back(i);
    arm_box_[at(pieces_[at(i)].arm)].extend(pieces_[at(i)].box);
  }
  index_.clear();
  for (int a = 0; a < arms; ++a) {
    std::vector<Aabb> boxes;
    for (int i : of_arm_[at(a)]) boxes.push_back(pieces_[at(i)].box);
    index_.emplace_back(boxes);
  }
}

bool Builder::findConflicts() {
  pending_.clear();
  edges_.clear();
  forced_ = 0;
  indexArms();
  const int arms = static_cast<int>(plan_.robots.size());
  for (int a = 0; a < arms; ++a) {
    for (int b = a + 1; b < arms; ++b) {
      if (arm_box_[at(a)].isEmpty() || arm_box_[at(b)].isEmpty()) continue;
      if (arm_box_[at(a)].exteriorDistance(arm_box_[at(b)]) > options_.clearance) continue;
      // Pairs the plan runs at once (each arm's pieces are in time order: a sliding window).
      const std::vector<int>& bs = of_arm_[at(b)];
      std::size_t first = 0;
      for (int i : of_arm_[at(a)]) {
        const Piece& pa = pieces_[at(i)];
        while (first < bs.size() && pieces_[at(bs[first])].t1 <= pa.t0 + kTimeTolerance) ++first;
        for (std::size_t k = first; k < bs.size() && pieces_[at(bs[k])].t0 < pa.t1 - kTimeTolerance; ++k) {
          orderOverlapping(i, bs[k]);
        }
      }
      addPredecessors(a, b);
      addPredecessors(b, a);
      reportPair(a, b);
    }
  }
  if (pending_.empty()) return false;
  for (const auto& [arm, t] : pending_) cuts_[at(arm)].insert(t);
  return true;
}

/// Pieces whose parts come within the clearance of an object at rest wait for the event that put it
/// there, or the event that takes it away waits for them, as the plan ordered them. Each rest is
/// tested only against the pieces the arms' box indexes find near it.
void Builder::addObjectEdges() {
  indexArms();
  std::vector<int> near;
  for (const Rest& rest : rests_) {
    const Aabb box = sweeps_.objectBox(rest.object, rest.X_WO);
    const double from_t = rest.from < 0 ? -1.0 : eventTime(rest.from);
    const double to_t = rest.to < 0 ? std::numeric_limits<double>::infinity() : eventTime(rest.to);
    auto eventSlot = [&](int position) { return std::make_pair(eventArm(position), slot_of_event_[at(position)]); };
    for (int a = 0; a < static_cast<int>(of_arm_.size()); ++a) {
      near.clear();
      index_[at(a)].near(box, options_.clearance, near);
      for (int k : near) {
        const int i = of_arm_[at(a)][at(k)];
        const Piece& p = pieces_[at(i)];
        if (!sweeps_.meetsObject(p, rest.object, rest.X_WO)) continue;
        const auto [arm, slot] = slot_of_piece_[at(i)];
        const bool before = rest.from >= 0 && p.t1 <= from_t + kTimeTolerance;
        const bool after = !before && rest.to >= 0 && p.t0 >= to_t - kTimeTolerance;
        if (before || (!after && rest.from >= 0)) {
          const auto [ea, es] = eventSlot(rest.from);
          before ? addEdge(arm, slot, ea, es, Edge::Why::kObject) : addEdge(ea, es, arm, slot, Edge::Why::kObject);
        }
        if (after || (!before && rest.to >= 0)) {
          const auto [ea, es] = eventSlot(rest.to);
          after ? addEdge(ea, es, arm, slot, Edge::Why::kObject) : addEdge(arm, slot, ea, es, Edge::Why::kObject);
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

}  // namespace dash::tpg::detail
