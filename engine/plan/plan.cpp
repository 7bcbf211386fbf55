#include "engine/plan/plan.h"

#include <algorithm>
#include <limits>

#include "engine/core/check.h"
#include "engine/scene/scene.h"

namespace dash {

JointVector RobotTrajectory::positionAt(double t) const {
  DASH_THROW_UNLESS(!points.empty(), "robot " + robot + ": the trajectory has no points");
  DASH_THROW_UNLESS(t >= 0.0, "robot " + robot + ": no position before t = 0 (asked for t = " + std::to_string(t) + ")");
  if (t <= points.front().t) return points.front().q;
  if (t >= points.back().t) return points.back().q;
  // First point strictly after t; the one before it is at or before t.
  const auto after = std::upper_bound(points.begin(), points.end(), t,
                                      [](double time, const TrajectoryPoint& p) { return time < p.t; });
  const TrajectoryPoint& b = *after;
  const TrajectoryPoint& a = *(after - 1);
  const double span = b.t - a.t;
  if (!(span > 0.0) || a.q.size() != b.q.size()) return a.q;  // malformed (non-increasing) times: no blend
  const double s = (t - a.t) / span;
  return a.q + s * (b.q - a.q);
}

double RobotTrajectory::endTime() const { return points.empty() ? 0.0 : points.back().t; }

const char* eventTypeName(PlanEvent::Type type) {
  switch (type) {
    case PlanEvent::Type::kGrasp:
      return "grasp";
    case PlanEvent::Type::kRelease:
      return "release";
    case PlanEvent::Type::kInspect:
      return "inspect";
  }
  return "?";
}

const RobotTrajectory* Plan::findRobot(const std::string& id) const {
  for (const auto& r : robots) {
    if (r.robot == id) return &r;
  }
  return nullptr;
}

RobotTrajectory* Plan::findRobot(const std::string& id) {
  for (auto& r : robots) {
    if (r.robot == id) return &r;
  }
  return nullptr;
}

void Plan::sortRobots(const Scene& scene) {
  auto rank = [&](const RobotTrajectory& r) {
    const int i = scene.robotIndex(r.robot);
    return i < 0 ? std::numeric_limits<int>::max() : i;
  };
  std::stable_sort(robots.begin(), robots.end(), [&](const RobotTrajectory& a, const RobotTrajectory& b) {
    const int ra = rank(a);
    const int rb = rank(b);
    return ra != rb ? ra < rb : a.robot < b.robot;
  });
}

double Plan::lastTime() const {
  double last = 0.0;
  for (const auto& r : robots) last = std::max(last, r.endTime());
  for (const auto& e : events) last = std::max(last, e.t);
  return last;
}

double Plan::jointPathLength() const {
  double total = 0.0;
  for (const RobotTrajectory& r : robots)
    for (std::size_t i = 1; i < r.points.size(); ++i) total += (r.points[i].q - r.points[i - 1].q).norm();
  return total;
}

}  // namespace dash
