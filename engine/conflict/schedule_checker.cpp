#include "engine/conflict/schedule_checker.h"

#include <algorithm>
#include <cstdint>

#include "engine/collision/segment_queries.h"
#include "engine/core/value_hash.h"

namespace dash {

namespace {
constexpr double kHeldObjectMargin = 0.15;  // a held object can stick out of a robot's reach box
constexpr std::size_t kMaxStill = 1u << 20;  // standing-still verdicts kept per lane (then forgotten, all)
// Robot-pair pieces a check must have before its pairs go to the lanes: below that, waking a thread
// costs more than it saves.
constexpr std::size_t kMinPiecesForLanes = 4;

double horizonOf(const std::vector<RobotTimeline>& timelines) {
  double h = 0.0;
  for (const RobotTimeline& t : timelines) h = std::max(h, t.end());
  return h;
}
}  // namespace

ScheduleChecker::Lane::Lane(const CollisionWorld& world, CollisionContext* shared)
    : own(shared ? nullptr : std::make_unique<CollisionContext>(world)),
      context(shared ? shared : own.get()),
      boxes(world, *context) {}

ScheduleChecker::ScheduleChecker(const CollisionWorld& world, CollisionContext& context, int threads)
    : world_(&world), context_(&context), none_(ObjectLayout::empty(world.scene())), pool_(checkLanes(threads)) {
  for (std::size_t lane = 0; lane < pool_.lanes(); ++lane)
    lanes_.push_back(std::make_unique<Lane>(world, lane == 0 ? &context : nullptr));
  const int n = world.robotCount();
  interact_.assign(static_cast<std::size_t>(n), std::vector<bool>(static_cast<std::size_t>(n), false));
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      Aabb ra = world.robot(a).reach, rb = world.robot(b).reach;
      ra.min().array() -= kHeldObjectMargin;
      ra.max().array() += kHeldObjectMargin;
      rb.min().array() -= kHeldObjectMargin;
      rb.max().array() += kHeldObjectMargin;
      interact_[a][b] = a != b && ra.intersects(rb);
    }
}

void ScheduleChecker::cutsOf(const RobotTimeline& timeline, const RobotTimeline* other, const ObjectTimeline* objects,
                             double from, double until, std::vector<double>& cuts) const {
  cuts.assign({from, until});
  timeline.breakpoints(from, until, cuts);
  if (other) other->breakpoints(from, until, cuts);
  if (objects) objects->breakpoints(from, until, cuts);
  for (auto it = std::upper_bound(extra_cuts_.begin(), extra_cuts_.end(), from); it != extra_cuts_.end() && *it < until; ++it)
    cuts.push_back(*it);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double a, double b) { return b - a < 1e-9; }), cuts.end());
  if (cuts.size() == 1) cuts.push_back(cuts.front());  // a single instant
}

// Each kind of pair is cut only where one of its own two parts changes: the robot against the resting
// objects where the robot's timeline or the object layout has a breakpoint, the robot against another
// robot where either timeline has one. Inside such a piece both move linearly (or stand), so one
// segment check covers it; cutting it also at unrelated robots' breakpoints would only repeat the same
// motion in smaller pieces. Pieces are checked in the order of their start times over all pairs (at
// equal times the objects first, then the robots in index order), so the first conflict found is the
// earliest and the check stops there.
//
// With several lanes, each lane first checks its own pairs (scanLane), each pair from its first piece
// up to its first conflict. Then the walk below goes through the pieces in that one order and takes
// each verdict a lane already has, checking itself any piece no lane reached: the first conflict of
// the walk is the one-lane answer, whatever the lanes did.
std::optional<ScheduleConflict> ScheduleChecker::check(const RobotTimeline& timeline, double from, double until,
                                                       const std::vector<RobotTimeline>& others,
                                                       const ObjectTimeline& objects) {
  const int r = timeline.robot();
  if (until == kForever) until = std::max({horizonOf(others), timeline.end(), from});
  // One sequence of pieces per pair: index 0 the resting objects, then each robot that may interact.
  pairs_.clear();
  pairs_.push_back({nullptr, {}, 0});
  cutsOf(timeline, nullptr, &objects, from, until, pairs_.back().cuts);
  std::size_t robot_pieces = 0;
  for (const RobotTimeline& o : others) {
    if (o.robot() == r || !mayInteract(r, o.robot())) continue;
    pairs_.push_back({&o, {}, 0});
    cutsOf(timeline, &o, nullptr, from, until, pairs_.back().cuts);
    robot_pieces += pairs_.back().cuts.size() - 1;
  }
  const std::size_t lanes = std::min(pool_.lanes(), pairs_.size());
  if (lanes > 1 && robot_pieces >= kMinPiecesForLanes) {
    earliest_.store(kForever, std::memory_order_relaxed);
    pool_.run([&](std::size_t lane) {
      if (lane < lanes) scanLane(lane, lanes, timeline, objects);
    });
  }
  PieceRecord own;
  for (;;) {
    PairPieces* next = nullptr;
    for (PairPieces& p : pairs_)
      if (p.next + 1 < p.cuts.size() && (!next || p.cuts[p.next] < next->cuts[next->next] - 1e-12)) next = &p;
    if (!next) return std::nullopt;
    const std::size_t j = next->next++;
    const PieceRecord* record = &own;
    if (j < next->checked) {
      record = &next->records[j];
    } else {
      own = {};
      checkPiece(*lanes_[0], timeline, *next, j, objects, own);
    }
    commit(*record);
    if (record->conflict) return record->conflict;
  }
}

void ScheduleChecker::scanLane(std::size_t lane, std::size_t lanes, const RobotTimeline& timeline,
                               const ObjectTimeline& objects) {
  for (;;) {
    PairPieces* next = nullptr;
    for (std::size_t k = lane; k < pairs_.size(); k += lanes) {
      PairPieces& p = pairs_[k];
      const bool stopped = !p.records.empty() && p.records.back().conflict;
      if (!stopped && p.checked + 1 < p.cuts.size() &&
          (!next || p.cuts[p.checked] < next->cuts[next->checked] - 1e-12))
        next = &p;
    }
    if (!next) return;
    const double u = next->cuts[next->checked];
    double earliest = earliest_.load(std::memory_order_relaxed);
    if (u > earliest + 1e-9) return;  // after a conflict found: check's walk stops before it
    checkPiece(*lanes_[lane], timeline, *next, next->checked, objects, next->records.emplace_back());
    ++next->checked;
    if (!next->records.back().conflict) continue;
    while (u < earliest && !earliest_.compare_exchange_weak(earliest, u, std::memory_order_relaxed)) {
    }
  }
}

namespace {
void add(CollisionCounters& to, const CollisionCounters& c, int sign) {
  const auto apply = [sign](std::uint64_t& x, std::uint64_t y) { x = sign > 0 ? x + y : x - y; };
  apply(to.configuration_checks, c.configuration_checks);
  apply(to.segment_checks, c.segment_checks);
  apply(to.narrowphase_calls, c.narrowphase_calls);
  apply(to.distance_queries, c.distance_queries);
  apply(to.cover_cleared, c.cover_cleared);
}
}  // namespace

void ScheduleChecker::commit(const PieceRecord& record) {
  add(context_->counters(), record.cost, +1);
  pieces_apart_ += record.apart;
  pieces_checked_ += record.exact;
  if (!record.standing_computed) return;
  if (still_.contains(record.standing_key)) {
    add(context_->counters(), record.standing_cost, -1);  // one lane would have found it
    return;
  }
  if (still_.size() >= kMaxStill) still_.clear();
  still_.emplace(record.standing_key, record.standing_free);
}

void ScheduleChecker::checkPiece(Lane& lane, const RobotTimeline& timeline, const PairPieces& pair, std::size_t j,
                                 const ObjectTimeline& objects, PieceRecord& record) {
  const CollisionCounters before = lane.context->counters();
  const int r = timeline.robot();
  const double u = pair.cuts[j], v = pair.cuts[j + 1], mid = 0.5 * (u + v);
  const RobotState self{r, timeline.at(u), timeline.heldAt(mid)};
  const JointVector self_end = timeline.at(v);
  if (!pair.other) {
    CollisionReport report;
    if (segmentInCollision(*world_, *lane.context, self, self_end, objects.layoutAt(mid), &report,
                           {CheckScope::kObjectsOnly})) {
      const int object = report.b.kind == CollisionElement::Kind::kObject ? report.b.index : -1;
      record.conflict = ScheduleConflict{u, -1, object, r};
    }
  } else if (piecesApart(lane, timeline, *pair.other, u, v)) {
    record.apart = true;
  } else {
    record.exact = true;
    const RobotTimeline& o = *pair.other;
    const bool standing = (self.q - self_end).cwiseAbs().maxCoeff() <= 1e-12;
    const RobotMotion motions[2] = {{self, self_end}, {{o.robot(), o.at(u), o.heldAt(mid)}, o.at(v)}};
    // Robot against robot only: each robot's own motion against what never moves was checked when it
    // was planned (roadmaps, replans, composite paths, transitions).
    if (!(standing && standingFreeOfSegment(lane, self, o, u, v, record)) &&
        motionsInCollision(*world_, *lane.context, motions, none_, nullptr, {CheckScope::kRobotsOnly}))
      record.conflict = ScheduleConflict{u, o.robot(), -1, r};
  }
  record.cost = lane.context->counters();
  add(record.cost, before, -1);
  lane.context->counters() = before;
}

bool ScheduleChecker::piecesApart(Lane& lane, const RobotTimeline& timeline, const RobotTimeline& other, double u,
                                  double v) {
  const std::optional<Aabb> mine = lane.boxes.pieceBox(timeline, u, v);
  if (!mine) return false;
  const std::optional<Aabb> theirs = lane.boxes.pieceBox(other, u, v);
  return theirs && !mine->intersects(*theirs);
}

std::size_t ScheduleChecker::StillKeyHash::operator()(const StillKey& key) const { return DoublesHash()(key.values); }

bool ScheduleChecker::standingFreeOfSegment(Lane& lane, const RobotState& self, const RobotTimeline& other, double u,
                                            double v, PieceRecord& record) const {
  // The other robot's straight segment [ta, tb] holding [u, v] (past its end it stands at its last point).
  const auto& pts = other.points();
  auto it = std::upper_bound(pts.begin(), pts.end(), u + 1e-12, [](double t, const TimedPoint& p) { return t < p.t; });
  if (it == pts.begin()) return false;
  const TimedPoint& a = *(it - 1);
  const bool past_end = it == pts.end();
  const double ta = a.t, tb = past_end ? kForever : it->t;
  if (v > tb + 1e-12) return false;
  const JointVector& qb = past_end ? a.q : it->q;
  // An instant to check (alsoCheckAt) inside the segment: its pieces are checked themselves, at it.
  if (auto cut = std::upper_bound(extra_cuts_.begin(), extra_cuts_.end(), ta - 1e-9);
      cut != extra_cuts_.end() && *cut < tb + 1e-9)
    return false;
  // What the other robot holds must not change inside the segment.
  const HeldObject held = other.heldAt(0.5 * (u + v));
  for (const HoldInterval& h : other.holds())
    if ((h.from > ta + 1e-12 && h.from < tb - 1e-12) || (h.to > ta + 1e-12 && h.to < tb - 1e-12)) return false;
  StillKey& k = record.standing_key;
  std::vector<double>& key = k.values;
  key.clear();
  key.push_back(self.robot);
  key.push_back(other.robot());
  key.push_back(ta);
  key.push_back(tb);
  key.insert(key.end(), self.q.data(), self.q.data() + self.q.size());
  key.insert(key.end(), a.q.data(), a.q.data() + a.q.size());
  key.insert(key.end(), qb.data(), qb.data() + qb.size());
  appendHeldKey(key, self.held);
  appendHeldKey(key, held);
  if (const auto found = still_.find(k); found != still_.end()) return found->second;
  const CollisionCounters before = lane.context->counters();
  const RobotMotion whole[2] = {{self, self.q}, {{other.robot(), a.q, held}, qb}};
  record.standing_free = !motionsInCollision(*world_, *lane.context, whole, none_, nullptr, {CheckScope::kRobotsOnly});
  record.standing_computed = true;
  record.standing_cost = lane.context->counters();
  add(record.standing_cost, before, -1);
  return record.standing_free;
}

void ScheduleChecker::alsoCheckAt(double t) { extra_cuts_.insert(std::upper_bound(extra_cuts_.begin(), extra_cuts_.end(), t), t); }

std::optional<ScheduleConflict> ScheduleChecker::checkResting(int object, const Pose& X_WO, double from,
                                                              const std::vector<RobotTimeline>& timelines, int except) {
  ObjectLayout only = ObjectLayout::empty(world_->scene());
  only.place(object, X_WO);
  for (const RobotTimeline& t : timelines) {
    if (t.robot() == except) continue;
    const auto& pts = t.points();
    // Every segment that ends after `from`, and the robot standing still at its last point.
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const bool last = i + 1 == pts.size();
      const double a = pts[i].t, b = last ? kForever : pts[i + 1].t;
      if (b <= from) continue;
      const double s = std::max(a, from);
      const RobotState state{t.robot(), t.at(s), t.heldAt(last ? s : 0.5 * (s + b))};
      if (state.held.object == object) continue;
      const JointVector end = last ? state.q : pts[i + 1].q;
      if (segmentInCollision(*world_, *context_, state, end, only, nullptr, {CheckScope::kObjectsOnly}))
        return ScheduleConflict{s, t.robot(), object};
    }
  }
  return std::nullopt;
}

}  // namespace dash
