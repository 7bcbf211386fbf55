#include "engine/motion/motion_constraints.h"

#include <cstdio>

namespace dash::lazy {

namespace {

std::string configurationText(const Scene& scene, int robot, const JointVector& q) {
  std::string out = scene.robots[robot].id + " q=(";
  for (int j = 0; j < q.size(); ++j) {
    char buffer[32];
    std::snprintf(buffer, sizeof buffer, "%s%.3f", j > 0 ? " " : "", q[j]);
    out += buffer;
  }
  return out + ")";
}

std::string regionText(const std::vector<Aabb>& boxes) {
  Aabb all;
  all.setEmpty();
  for (const Aabb& b : boxes) all.extend(b);
  char buffer[192];
  std::snprintf(buffer, sizeof buffer, "%zu box%s in [%.3f, %.3f] x [%.3f, %.3f] x [%.3f, %.3f] m", boxes.size(),
                boxes.size() == 1 ? "" : "es", all.min().x(), all.max().x(), all.min().y(), all.max().y(),
                all.min().z(), all.max().z());
  return buffer;
}

}  // namespace

std::string MotionConstraint::describe(const Scene& scene) const {
  std::string out;
  for (std::size_t i = 0; i < histories.size(); ++i) {
    const History& h = histories[i];
    const std::string text =
        scene.robots[h.robot].id + (h.step >= 0 ? " at step " + std::to_string(h.step) : " on its way home");
    out += i == 0 ? text : (i == 1 ? " (" : ", ") + text;
  }
  if (histories.size() > 1) out += ")";
  if (object >= 0) out += (out.empty() ? "" : " ") + std::string("in the way: ") + scene.objects[object].id;
  out += "; region: ";
  std::string parts;
  if (!region.empty()) parts = regionText(region);
  for (const auto& [robot, q] : configurations) parts += (parts.empty() ? "" : ", ") + configurationText(scene, robot, q);
  if (hasTimeRegion()) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "t in [%.3f, %.3f] s", t_begin, t_end);
    parts += (parts.empty() ? "" : "; ") + std::string(buffer);
  }
  // Last, every box of the region (what the motion query keeps out of), for the results database and
  // whoever checks a path against it: "; boxes: [x0 y0 z0 x1 y1 z1] [...]", metres, 0.1 mm.
  std::string boxes;
  for (const Aabb& b : region) {
    char buffer[128];
    std::snprintf(buffer, sizeof buffer, " [%.4f %.4f %.4f %.4f %.4f %.4f]", b.min().x(), b.min().y(), b.min().z(),
                  b.max().x(), b.max().y(), b.max().z());
    boxes += buffer;
  }
  return out + (parts.empty() ? "none" : parts) + (boxes.empty() ? "" : "; boxes:" + boxes);
}

MotionConstraint::History historyOf(const TaskPlan& plan, int robot, int step) {
  MotionConstraint::History h;
  h.robot = robot;
  h.step = step;
  const int last = step < 0 ? static_cast<int>(plan.steps.size()) - 1 : step;
  for (int k = 0; k <= last && k < static_cast<int>(plan.steps.size()); ++k) {
    const TaskArc& a = plan.steps[k].action;
    if (a.robot == robot || a.robot2 == robot) h.arcs.push_back(plan.steps[k].arc.value());
  }
  return h;
}

namespace {
bool sameBoxes(const std::vector<Aabb>& a, const std::vector<Aabb>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].min() != b[i].min() || a[i].max() != b[i].max()) return false;
  return true;
}
}  // namespace

bool MotionConstraintSet::contains(const MotionConstraint& c) const {
  if (c.histories.empty()) return false;
  for (std::size_t i = 0; i < constraints_.size(); ++i)
    if (const MotionConstraint& known = constraints_[i]; in_force_[i] && !known.histories.empty() &&
        known.histories.front().robot == c.histories.front().robot &&
        known.histories.front().arcs == c.histories.front().arcs && sameBoxes(known.region, c.region))
      return true;
  return false;
}

std::vector<std::size_t> MotionConstraintSet::liftAll() {
  std::vector<std::size_t> lifted;
  for (std::size_t i = 0; i < constraints_.size(); ++i)
    if (in_force_[i]) {
      in_force_[i] = false;
      lifted.push_back(i);
    }
  return lifted;
}

std::vector<std::size_t> MotionConstraintSet::regionIndicesFor(const TaskPlan& plan, int robot, int step,
                                                               const JointVector& q) const {
  std::vector<std::size_t> out;
  std::vector<std::uint32_t> arcs;
  bool computed = false;
  for (std::size_t i = 0; i < constraints_.size(); ++i) {
    const MotionConstraint& c = constraints_[i];
    if (!in_force_[i] || c.region.empty() || c.histories.empty()) continue;
    const MotionConstraint::History& h = c.histories.front();
    if (h.robot != robot) continue;
    if (h.q.size() > 0 && (h.q.size() != q.size() || (h.q - q).cwiseAbs().maxCoeff() > 1e-9)) continue;
    if (!computed) {
      arcs = historyOf(plan, robot, step).arcs;
      computed = true;
    }
    if (h.arcs == arcs) out.push_back(i);
  }
  return out;
}

std::vector<Aabb> MotionConstraintSet::regionsFor(const TaskPlan& plan, int robot, int step,
                                                  const JointVector& q) const {
  std::vector<Aabb> out;
  for (std::size_t i : regionIndicesFor(plan, robot, step, q))
    out.insert(out.end(), constraints_[i].region.begin(), constraints_[i].region.end());
  return out;
}

std::vector<std::size_t> MotionConstraintSet::liftRegionsFor(const TaskPlan& plan, int robot, int step,
                                                             const JointVector& q) {
  std::vector<std::size_t> lifted = regionIndicesFor(plan, robot, step, q);
  for (std::size_t i : lifted) in_force_[i] = false;
  return lifted;
}

}  // namespace dash::lazy
