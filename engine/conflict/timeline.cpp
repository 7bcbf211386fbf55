#include "engine/conflict/timeline.h"

#include <algorithm>

#include "engine/core/check.h"

namespace dash {

RobotTimeline::RobotTimeline(int robot, const JointVector& home) : robot_(robot) { points_.push_back({0.0, home}); }

JointVector RobotTimeline::at(double t) const {
  if (t <= points_.front().t) return points_.front().q;
  if (t >= points_.back().t) return points_.back().q;
  auto it = std::upper_bound(points_.begin(), points_.end(), t, [](double v, const TimedPoint& p) { return v < p.t; });
  const TimedPoint& b = *it;
  const TimedPoint& a = *(it - 1);
  const double s = (t - a.t) / (b.t - a.t);
  return a.q + s * (b.q - a.q);
}

HeldObject RobotTimeline::heldAt(double t) const {
  for (const HoldInterval& h : holds_)
    if (t >= h.from && t < h.to) return h.held;
  return {};
}

HeldObject RobotTimeline::heldAtEnd() const {
  if (!holds_.empty() && holds_.back().to == kForever) return holds_.back().held;
  return {};
}

void RobotTimeline::breakpoints(double a, double b, std::vector<double>& out) const {
  for (const TimedPoint& p : points_)
    if (p.t > a && p.t < b) out.push_back(p.t);
  for (const HoldInterval& h : holds_) {
    if (h.from > a && h.from < b) out.push_back(h.from);
    if (h.to > a && h.to < b) out.push_back(h.to);
  }
}

void RobotTimeline::append(double t, const JointVector& q) {
  const TimedPoint& last = points_.back();
  if (t <= last.t + 1e-9) {
    DASH_DEMAND_MSG((q - last.q).cwiseAbs().maxCoeff() < 1e-9, "timeline points must move forward in time");
    return;
  }
  points_.push_back({t, q});
}

void RobotTimeline::grasp(double t, const HeldObject& held) { holds_.push_back({t, kForever, held}); }

void RobotTimeline::release(double t) {
  DASH_DEMAND(!holds_.empty() && holds_.back().to == kForever);
  holds_.back().to = t;
}

void RobotTimeline::rewind(const Mark& mark) {
  DASH_DEMAND(mark.points >= 1 && mark.points <= points_.size());
  points_.resize(mark.points);
  holds_ = mark.holds;
}

ObjectTimeline::ObjectTimeline(const ObjectLayout& start) : start_(start) {}

void ObjectTimeline::pick(int object, double t) { changes_.push_back({t, object, false, Pose::Identity()}); }

void ObjectTimeline::place(int object, double t, const Pose& X_WO) { changes_.push_back({t, object, true, X_WO}); }

ObjectLayout ObjectTimeline::layoutAt(double t) const {
  // Changes may be recorded out of time order (independent threads are scheduled in plan order):
  // apply, per object, the latest change at or before t.
  ObjectLayout layout = start_;
  std::vector<double> latest(static_cast<std::size_t>(layout.size()), -1.0);
  for (const Change& c : changes_) {
    if (c.t > t || c.t < latest[c.object]) continue;
    latest[c.object] = c.t;
    if (c.present) {
      layout.place(c.object, c.X_WO);
    } else {
      layout.remove(c.object);
    }
  }
  return layout;
}

void ObjectTimeline::rewind(std::size_t mark) {
  DASH_DEMAND(mark <= changes_.size());
  changes_.resize(mark);
}

void ObjectTimeline::breakpoints(double a, double b, std::vector<double>& out) const {
  for (const Change& c : changes_)
    if (c.t > a && c.t < b) out.push_back(c.t);
}

}  // namespace dash
