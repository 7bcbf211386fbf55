#include "engine/conflict/schedule_checker.h"

#include <algorithm>

#include "engine/collision/segment_queries.h"

namespace dash {

namespace {
constexpr double kHeldObjectMargin = 0.15;  // a held object can stick out of a robot's reach box

double horizonOf(const std::vector<RobotTimeline>& timelines) {
  double h = 0.0;
  for (const RobotTimeline& t : timelines) h = std::max(h, t.end());
  return h;
}
}  // namespace

ScheduleChecker::ScheduleChecker(const CollisionWorld& world, CollisionContext& context)
    : world_(&world), context_(&context) {
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

std::optional<ScheduleConflict> ScheduleChecker::check(const RobotTimeline& timeline, double from, double until,
                                                       const std::vector<RobotTimeline>& others,
                                                       const ObjectTimeline& objects) {
  const int r = timeline.robot();
  if (until == kForever) until = std::max({horizonOf(others), timeline.end(), from});
  std::vector<double> cuts{from, until};
  timeline.breakpoints(from, until, cuts);
  objects.breakpoints(from, until, cuts);
  for (const RobotTimeline& o : others)
    if (o.robot() != r && mayInteract(r, o.robot())) o.breakpoints(from, until, cuts);
  for (auto it = std::upper_bound(extra_cuts_.begin(), extra_cuts_.end(), from); it != extra_cuts_.end() && *it < until; ++it)
    cuts.push_back(*it);
  std::sort(cuts.begin(), cuts.end());
  cuts.erase(std::unique(cuts.begin(), cuts.end(), [](double a, double b) { return b - a < 1e-9; }), cuts.end());
  if (cuts.size() == 1) cuts.push_back(cuts.front());  // a single instant

  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    const double u = cuts[i], v = cuts[i + 1], mid = 0.5 * (u + v);
    const RobotState self{r, timeline.at(u), timeline.heldAt(mid)};
    const JointVector self_end = timeline.at(v);
    const ObjectLayout layout = objects.layoutAt(mid);
    CollisionReport report;
    if (segmentInCollision(*world_, *context_, self, self_end, layout, &report, {CheckScope::kObjectsOnly})) {
      const int j = report.b.kind == CollisionElement::Kind::kObject ? report.b.index : -1;
      return ScheduleConflict{u, -1, j, r};
    }
    const ObjectLayout none = ObjectLayout::empty(world_->scene());
    for (const RobotTimeline& o : others) {
      if (o.robot() == r || !mayInteract(r, o.robot())) continue;
      const RobotMotion motions[2] = {{self, self_end}, {{o.robot(), o.at(u), o.heldAt(mid)}, o.at(v)}};
      if (motionsInCollision(*world_, *context_, motions, none, nullptr, {CheckScope::kStaticOnly}))
        return ScheduleConflict{u, o.robot(), -1, r};
    }
  }
  return std::nullopt;
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
