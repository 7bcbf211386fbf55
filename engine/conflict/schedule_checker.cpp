#include "engine/conflict/schedule_checker.h"

#include <algorithm>
#include <cstdint>
#include <cstring>

#include "engine/collision/segment_queries.h"

namespace dash {

namespace {
constexpr double kHeldObjectMargin = 0.15;  // a held object can stick out of a robot's reach box
constexpr std::size_t kMaxStill = 1u << 20;  // standing-still verdicts kept (then forgotten, all)

double horizonOf(const std::vector<RobotTimeline>& timelines) {
  double h = 0.0;
  for (const RobotTimeline& t : timelines) h = std::max(h, t.end());
  return h;
}
}  // namespace

ScheduleChecker::ScheduleChecker(const CollisionWorld& world, CollisionContext& context)
    : world_(&world), context_(&context), none_(ObjectLayout::empty(world.scene())), boxes_(world, context) {
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
std::optional<ScheduleConflict> ScheduleChecker::check(const RobotTimeline& timeline, double from, double until,
                                                       const std::vector<RobotTimeline>& others,
                                                       const ObjectTimeline& objects) {
  const int r = timeline.robot();
  if (until == kForever) until = std::max({horizonOf(others), timeline.end(), from});
  // One sequence of pieces per pair: index 0 the resting objects, then each robot that may interact.
  pairs_.clear();
  pairs_.push_back({nullptr, {}, 0});
  cutsOf(timeline, nullptr, &objects, from, until, pairs_.back().cuts);
  for (const RobotTimeline& o : others) {
    if (o.robot() == r || !mayInteract(r, o.robot())) continue;
    pairs_.push_back({&o, {}, 0});
    cutsOf(timeline, &o, nullptr, from, until, pairs_.back().cuts);
  }
  for (;;) {
    PairPieces* next = nullptr;
    for (PairPieces& p : pairs_)
      if (p.next + 1 < p.cuts.size() && (!next || p.cuts[p.next] < next->cuts[next->next] - 1e-12)) next = &p;
    if (!next) return std::nullopt;
    const double u = next->cuts[next->next], v = next->cuts[next->next + 1], mid = 0.5 * (u + v);
    ++next->next;
    const RobotState self{r, timeline.at(u), timeline.heldAt(mid)};
    const JointVector self_end = timeline.at(v);
    if (!next->other) {
      CollisionReport report;
      if (segmentInCollision(*world_, *context_, self, self_end, objects.layoutAt(mid), &report,
                             {CheckScope::kObjectsOnly})) {
        const int j = report.b.kind == CollisionElement::Kind::kObject ? report.b.index : -1;
        return ScheduleConflict{u, -1, j, r};
      }
      continue;
    }
    const RobotTimeline& o = *next->other;
    if (piecesApart(timeline, o, u, v)) continue;
    ++pieces_checked_;
    if ((self.q - self_end).cwiseAbs().maxCoeff() <= 1e-12 && standingFreeOfSegment(self, o, u, v)) continue;
    const RobotMotion motions[2] = {{self, self_end}, {{o.robot(), o.at(u), o.heldAt(mid)}, o.at(v)}};
    // Robot against robot only: each robot's own motion against what never moves was checked when it
    // was planned (roadmaps, replans, composite paths, transitions).
    if (motionsInCollision(*world_, *context_, motions, none_, nullptr, {CheckScope::kRobotsOnly}))
      return ScheduleConflict{u, o.robot(), -1, r};
  }
}

bool ScheduleChecker::piecesApart(const RobotTimeline& timeline, const RobotTimeline& other, double u, double v) {
  const std::optional<Aabb> mine = boxes_.pieceBox(timeline, u, v);
  if (!mine) return false;
  const std::optional<Aabb> theirs = boxes_.pieceBox(other, u, v);
  if (!theirs || mine->intersects(*theirs)) return false;
  ++pieces_apart_;
  return true;
}

std::size_t ScheduleChecker::StillKeyHash::operator()(const StillKey& key) const {
  std::size_t h = 1469598103934665603ull;
  for (const double x : key.values) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    h = (h ^ bits) * 1099511628211ull;
  }
  return h;
}

namespace {
void appendHeld(std::vector<double>& key, const HeldObject& held) {
  key.push_back(held.object);
  key.push_back(held.in_transit ? 1.0 : 0.0);
  if (!held.holding()) return;
  const double* m = held.X_TO.matrix().data();
  key.insert(key.end(), m, m + 12);  // the rotation and translation columns
}
}  // namespace

bool ScheduleChecker::standingFreeOfSegment(const RobotState& self, const RobotTimeline& other, double u, double v) {
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
  StillKey k;
  std::vector<double>& key = k.values;
  key.push_back(self.robot);
  key.push_back(other.robot());
  key.push_back(ta);
  key.push_back(tb);
  key.insert(key.end(), self.q.data(), self.q.data() + self.q.size());
  key.insert(key.end(), a.q.data(), a.q.data() + a.q.size());
  key.insert(key.end(), qb.data(), qb.data() + qb.size());
  appendHeld(key, self.held);
  appendHeld(key, held);
  if (const auto found = still_.find(k); found != still_.end()) return found->second;
  const RobotMotion whole[2] = {{self, self.q}, {{other.robot(), a.q, held}, qb}};
  const bool free = !motionsInCollision(*world_, *context_, whole, none_, nullptr, {CheckScope::kRobotsOnly});
  if (still_.size() >= kMaxStill) still_.clear();
  still_.emplace(std::move(k), free);
  return free;
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
