#include "engine/collision/segment_queries.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/collision/collision_internal.h"
#include "engine/collision/cover_check.h"
#include "engine/collision/distance_queries.h"
#include "engine/core/check.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

using Interval = CollisionContext::Scratch::Interval;

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Bound for the held object: the TCP's lever plus the object's farthest point from the TCP for a
/// revolute joint; a prismatic joint moves every point by exactly |dq|.
double heldDisplacement(const CollisionWorld& world, int r, const JointVector& dq_abs, const HeldObject& held) {
  const RobotGeometry& rg = world.robot(r);
  const bool revolute = rg.model->kinematics == KinematicsKind::kUrDh;
  double extent = 0.0;
  if (held.holding()) {
    const Vec3 half = 0.5 * world.scene().objects[at(held.object)].shape.size;
    extent = held.X_TO.translation().norm() + half.norm();
  }
  double d = 0.0;
  for (Eigen::Index i = 0; i < dq_abs.size(); ++i) d += dq_abs[i] * (rg.tcp_lever[i] + (revolute ? extent : 0.0));
  return d;
}

double bodyDisplacement(const RobotGeometry& rg, int b, const JointVector& dq_abs) {
  return dq_abs.dot(rg.body_lever[at(b)]);
}

Aabb grown(const Aabb& box, double margin) { return Aabb(box.min().array() - margin, box.max().array() + margin); }

JointVector interpolate(const JointVector& q0, const JointVector& q1, double t) { return q0 + t * (q1 - q0); }

/// Stores robot r's posed body boxes and held-object box as a new slot of step_boxes.
int saveBoxes(CollisionContext& context, int r) {
  auto& s = context.scratch();
  const auto& posed = s.robots[at(r)];
  const std::size_t stride = posed.body_aabb.size() + 1;
  const int slot = static_cast<int>(s.step_boxes.size() / stride);
  s.step_boxes.insert(s.step_boxes.end(), posed.body_aabb.begin(), posed.body_aabb.end());
  s.step_boxes.push_back(posed.held_object >= 0 ? posed.held_aabb : Aabb());
  return slot;
}

/// Swept boxes of the part of the segment between two saved steps, `fraction` of the whole segment
/// long: each box at both ends, grown by half the displacement bound over that part (every
/// intermediate pose lies within that distance of one end). Bodies into swept_body; returns the union.
Aabb sweptBetween(CollisionContext& context, int bodies, int slot_a, int slot_b, double fraction, double held_d,
                  bool holding, Aabb& held_swept) {
  auto& s = context.scratch();
  const std::size_t stride = static_cast<std::size_t>(bodies) + 1;
  const Aabb* a = &s.step_boxes[at(slot_a) * stride];
  const Aabb* b = &s.step_boxes[at(slot_b) * stride];
  s.swept_body.resize(at(bodies));
  Aabb whole;
  whole.setEmpty();
  for (int k = 0; k < bodies; ++k) {
    s.swept_body[at(k)] = grown(a[k].merged(b[k]), 0.5 * fraction * s.displacement[at(k)]);
    whole.extend(s.swept_body[at(k)]);
  }
  if (holding) {
    held_swept = grown(a[bodies].merged(b[bodies]), 0.5 * fraction * held_d);
    whole.extend(held_swept);
  }
  return whole;
}

bool anyBodyMeets(const std::vector<Aabb>& swept, const Aabb& box) {
  return std::any_of(swept.begin(), swept.end(), [&](const Aabb& b) { return b.intersects(box); });
}

/// Whether `box` meets the current swept boxes: their union first, then each body's and the held object's.
bool meetsSwept(const CollisionContext::Scratch& s, const Aabb& box, const Aabb& whole, bool holding,
                const Aabb& held_swept) {
  if (!whole.intersects(box)) return false;
  return (holding && held_swept.intersects(box)) || anyBodyMeets(s.swept_body, box);
}

/// Keeps the pairs of `full` that meet the swept boxes, in context.scratch().candidates.
void narrowCandidates(const CollisionWorld& world, CollisionContext& context, const detail::CandidateView& full,
                      const Aabb& whole, bool holding, const Aabb& held_swept) {
  auto& s = context.scratch();
  auto& c = s.candidates;
  c.obstacles.clear();
  c.held_obstacles.clear();
  c.objects.clear();
  c.self_pairs.clear();
  c.held_vs_bodies.clear();
  for (const int i : full.obstacles) {
    const Aabb& box = world.obstacles()[at(i)].aabb;
    if (whole.intersects(box) && anyBodyMeets(s.swept_body, box)) c.obstacles.push_back(i);
  }
  if (holding) {
    for (const int i : full.held_obstacles) {
      if (held_swept.intersects(world.obstacles()[at(i)].aabb)) c.held_obstacles.push_back(i);
    }
    for (const int b : full.held_vs_bodies) {
      if (held_swept.intersects(s.swept_body[at(b)])) c.held_vs_bodies.push_back(b);
    }
  }
  for (const int j : full.objects) {
    if (meetsSwept(s, s.object_aabb[at(j)], whole, holding, held_swept)) c.objects.push_back(j);
  }
  for (const auto& pair : full.self_pairs) {
    if (s.swept_body[at(pair.first)].intersects(s.swept_body[at(pair.second)])) c.self_pairs.push_back(pair);
  }
  c.robots.clear();
  for (const int p : full.robots) {
    if (meetsSwept(s, detail::postureBox(s.robots[at(p)]), whole, holding, held_swept)) c.robots.push_back(p);
  }
}

/// True if any pair of `view` meets the current swept boxes.
bool anyCandidateMeets(const CollisionWorld& world, const CollisionContext::Scratch& s, const detail::CandidateView& view,
                       const Aabb& whole, bool holding, const Aabb& held_swept) {
  for (const int i : view.obstacles) {
    const Aabb& box = world.obstacles()[at(i)].aabb;
    if (whole.intersects(box) && anyBodyMeets(s.swept_body, box)) return true;
  }
  for (const auto& pair : view.self_pairs) {
    if (s.swept_body[at(pair.first)].intersects(s.swept_body[at(pair.second)])) return true;
  }
  for (const int j : view.objects) {
    if (meetsSwept(s, s.object_aabb[at(j)], whole, holding, held_swept)) return true;
  }
  for (const int p : view.robots) {
    if (meetsSwept(s, detail::postureBox(s.robots[at(p)]), whole, holding, held_swept)) return true;
  }
  if (!holding) return false;
  for (const int i : view.held_obstacles) {
    if (held_swept.intersects(world.obstacles()[at(i)].aabb)) return true;
  }
  for (const int b : view.held_vs_bodies) {
    if (held_swept.intersects(s.swept_body[at(b)])) return true;
  }
  return false;
}

/// Visits steps 1 .. n-1 midpoint first, then the midpoints of each half, and so on.
template <class Visit>
bool forEachStepCoarseToFine(CollisionContext& context, int n, Visit visit) {
  auto& queue = context.scratch().intervals;
  queue.clear();
  queue.push_back({0, n, -1, -1});
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const Interval iv = queue[head];
    if (iv.hi - iv.lo < 2) continue;
    const int mid = (iv.lo + iv.hi) / 2;
    if (visit(mid)) return true;
    queue.push_back({iv.lo, mid, -1, -1});
    queue.push_back({mid, iv.hi, -1, -1});
  }
  return false;
}

/// One robot's segment with the resting set already prepared, and against the posed robots standing
/// still in `parked`. The steps are visited coarse to fine; a part of the segment whose swept boxes meet
/// no candidate pair is free and not refined further.
bool robotSegment(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                  const JointVector& q_end, CollisionReport* report, const SegmentOptions& options,
                  std::span<const int> parked = {}) {
  const int r = start.robot;
  DASH_DEMAND(r >= 0 && r < world.robotCount());
  DASH_DEMAND_MSG(q_end.size() == start.q.size(), "segment end points differ in size");
  const RobotGeometry& rg = world.robot(r);
  const int bodies = static_cast<int>(rg.bodies.size());
  const bool holding = start.held.holding();
  auto& s = context.scratch();
  detail::CandidateView full;
  if (options.scope != CheckScope::kRobotsOnly) full = detail::fullCandidates(world, context, r, options.scope);
  if (options.scope != CheckScope::kObjectsOnly) full.robots = parked;
  auto check_posed = [&](double fraction, const detail::CandidateView& view) {
    ++context.counters().configuration_checks;
    if (!detail::checkPosedRobot(world, context, r, view, report)) return false;
    if (report != nullptr) report->segment_fraction = fraction;
    return true;
  };

  s.step_boxes.clear();
  s.intervals.clear();
  detail::poseRobot(world, context, r, start.q, start.held);
  if (options.check_endpoints && check_posed(0.0, full)) return true;
  const int slot_start = saveBoxes(context, r);
  detail::poseRobot(world, context, r, q_end, start.held);
  if (options.check_endpoints && check_posed(1.0, full)) return true;
  const int slot_end = saveBoxes(context, r);

  const JointVector dq_abs = (q_end - start.q).cwiseAbs();
  s.displacement.resize(at(bodies));
  for (int b = 0; b < bodies; ++b) s.displacement[at(b)] = bodyDisplacement(rg, b, dq_abs);
  const double held_d = heldDisplacement(world, r, dq_abs, start.held);
  const int n = segmentSteps(world, r, start.q, q_end, start.held, options.resolution);

  Aabb held_swept;
  const Aabb whole = sweptBetween(context, bodies, slot_start, slot_end, 1.0, held_d, holding, held_swept);
  narrowCandidates(world, context, full, whole, holding, held_swept);
  const auto& c = s.candidates;
  const detail::CandidateView narrowed{c.obstacles, c.held_obstacles, c.objects, c.self_pairs, c.held_vs_bodies,
                                       c.robots};
  if (!anyCandidateMeets(world, s, narrowed, whole, holding, held_swept)) return false;
  if (detail::coverOn(world)) {
    // The steps in the same order as below; those the covers clear are free to the exact check too,
    // and so are those the swept boxes below skip, so the first colliding step found is the same.
    thread_local std::vector<std::uint8_t> cleared;
    detail::coverSegmentSteps(world, context, start, q_end, n, narrowed, cleared);
    context.counters().cover_cleared += static_cast<std::uint64_t>(std::count(cleared.begin(), cleared.end(), 1));
    return forEachStepCoarseToFine(context, n, [&](int mid) {
      if (cleared[at(mid)] != 0) return false;
      const double t = static_cast<double>(mid) / n;
      detail::poseRobot(world, context, r, interpolate(start.q, q_end, t), start.held);
      return check_posed(t, narrowed);
    });
  }

  s.intervals.push_back({0, n, slot_start, slot_end});
  for (std::size_t head = 0; head < s.intervals.size(); ++head) {
    const Interval iv = s.intervals[head];  // a copy: the queue grows below
    if (iv.hi - iv.lo < 2) continue;
    if (head > 0) {
      const double fraction = static_cast<double>(iv.hi - iv.lo) / n;
      const Aabb part = sweptBetween(context, bodies, iv.slot_lo, iv.slot_hi, fraction, held_d, holding, held_swept);
      if (!anyCandidateMeets(world, s, narrowed, part, holding, held_swept)) continue;
    }
    const int mid = (iv.lo + iv.hi) / 2;
    const double t = static_cast<double>(mid) / n;
    detail::poseRobot(world, context, r, interpolate(start.q, q_end, t), start.held);
    if (check_posed(t, narrowed)) return true;
    const int slot_mid = saveBoxes(context, r);
    s.intervals.push_back({iv.lo, mid, iv.slot_lo, slot_mid});
    s.intervals.push_back({mid, iv.hi, slot_mid, iv.slot_hi});
  }
  return false;
}

/// Whole swept box of robot r (bodies and held object) along q0 -> q1.
Aabb wholeSweptBox(const CollisionWorld& world, CollisionContext& context, const RobotMotion& m) {
  const int r = m.start.robot;
  const RobotGeometry& rg = world.robot(r);
  const JointVector dq_abs = (m.q_end - m.start.q).cwiseAbs();
  double d = heldDisplacement(world, r, dq_abs, m.start.held);
  for (int b = 0; b < static_cast<int>(rg.bodies.size()); ++b) d = std::max(d, bodyDisplacement(rg, b, dq_abs));
  const auto& posed = context.scratch().robots[at(r)];
  Aabb box;
  box.setEmpty();
  for (const JointVector* q : {&m.start.q, &m.q_end}) {
    detail::poseRobot(world, context, r, *q, m.start.held);
    box.extend(posed.aabb);
    if (m.start.held.holding()) box.extend(posed.held_aabb);
  }
  return grown(box, 0.5 * d);
}

}  // namespace

double bodyDisplacementBound(const CollisionWorld& world, int robot, int body, const JointVector& q0,
                             const JointVector& q1) {
  return bodyDisplacement(world.robot(robot), body, (q1 - q0).cwiseAbs());
}

double heldDisplacementBound(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                             const HeldObject& held) {
  return held.holding() ? heldDisplacement(world, robot, (q1 - q0).cwiseAbs(), held) : 0.0;
}

double segmentDisplacementBound(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                                const HeldObject& held) {
  const RobotGeometry& rg = world.robot(robot);
  const JointVector dq_abs = (q1 - q0).cwiseAbs();
  double d = heldDisplacement(world, robot, dq_abs, held);  // includes the TCP itself
  for (int b = 0; b < static_cast<int>(rg.bodies.size()); ++b) d = std::max(d, bodyDisplacement(rg, b, dq_abs));
  return d;
}

int segmentSteps(const CollisionWorld& world, int robot, const JointVector& q0, const JointVector& q1,
                 const HeldObject& held, double resolution) {
  DASH_DEMAND(resolution > 0.0);
  const double d = segmentDisplacementBound(world, robot, q0, q1, held);
  return std::max(1, static_cast<int>(std::ceil(d / resolution)));
}

void sweptPartBoxes(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                    const JointVector& q_end, std::vector<Aabb>& boxes) {
  const int r = start.robot;
  const RobotGeometry& rg = world.robot(r);
  const JointVector dq_abs = (q_end - start.q).cwiseAbs();
  const auto& posed = context.scratch().robots[at(r)];
  const int bodies = static_cast<int>(rg.bodies.size());
  const std::size_t first = boxes.size();
  detail::poseRobot(world, context, r, start.q, start.held);
  boxes.insert(boxes.end(), posed.body_aabb.begin(), posed.body_aabb.end());
  if (start.held.holding()) boxes.push_back(posed.held_aabb);
  detail::poseRobot(world, context, r, q_end, start.held);
  for (int b = 0; b < bodies; ++b)
    boxes[first + at(b)] = grown(boxes[first + at(b)].merged(posed.body_aabb[at(b)]), 0.5 * bodyDisplacement(rg, b, dq_abs));
  if (start.held.holding())
    boxes.back() = grown(boxes.back().merged(posed.held_aabb), 0.5 * heldDisplacement(world, r, dq_abs, start.held));
}

bool segmentInCollision(const CollisionWorld& world, CollisionContext& context, const RobotState& start,
                        const JointVector& q_end, const ObjectLayout& layout, CollisionReport* report,
                        const SegmentOptions& options) {
  ++context.counters().segment_checks;
  detail::prepareResting(world, context, layout, std::span<const RobotState>(&start, 1));
  return robotSegment(world, context, start, q_end, report, options);
}

bool motionsInCollision(const CollisionWorld& world, CollisionContext& context, std::span<const RobotMotion> motions,
                        const ObjectLayout& layout, CollisionReport* report, const SegmentOptions& options) {
  return motionsAmongParked(world, context, motions, {}, layout, report, options);
}

bool motionsAmongParked(const CollisionWorld& world, CollisionContext& context, std::span<const RobotMotion> motions,
                        std::span<const RobotState> parked, const ObjectLayout& layout, CollisionReport* report,
                        const SegmentOptions& options) {
  ++context.counters().segment_checks;
  std::vector<RobotState> states;
  states.reserve(motions.size() + parked.size());
  for (const RobotMotion& m : motions) states.push_back(m.start);
  states.insert(states.end(), parked.begin(), parked.end());
  for (std::size_t i = motions.size(); i < states.size(); ++i)
    for (std::size_t k = 0; k < i; ++k) DASH_DEMAND_MSG(states[k].robot != states[i].robot, "a robot appears twice");
  detail::prepareResting(world, context, layout, states);
  states.resize(motions.size());

  // Each robot's whole swept box; the parked robots are posed once, and only those within reach of a
  // swept box are checked against the movers.
  std::vector<Aabb> whole;
  whole.reserve(motions.size());
  Aabb reach;
  reach.setEmpty();
  for (const RobotMotion& m : motions) {
    whole.push_back(wholeSweptBox(world, context, m));
    reach.extend(whole.back());
  }
  std::vector<int> near;
  detail::poseParked(world, context, parked, near);
  std::erase_if(near, [&](int p) { return !detail::postureBox(context.scratch().robots[at(p)]).intersects(reach); });

  auto check_states = [&](double t) {
    ++context.counters().configuration_checks;
    for (std::size_t i = 0; i < motions.size(); ++i) states[i].q = interpolate(motions[i].start.q, motions[i].q_end, t);
    if (!detail::checkStates(world, context, states, options.scope, report, near)) return false;
    if (report != nullptr) report->segment_fraction = t;
    return true;
  };
  if (options.check_endpoints && (check_states(0.0) || check_states(1.0))) return true;

  // Moving robots whose swept boxes meet no other's cannot collide with each other along the motion:
  // each is then checked alone (with its own refinement, against the parked robots near it);
  // otherwise all together at every step.
  bool apart = true;
  if (options.scope != CheckScope::kObjectsOnly) {
    for (std::size_t i = 0; i < whole.size() && apart; ++i) {
      for (std::size_t k = i + 1; k < whole.size() && apart; ++k) apart = !whole[i].intersects(whole[k]);
    }
  }
  if (apart && options.scope == CheckScope::kRobotsOnly && near.empty()) return false;
  if (apart) {
    SegmentOptions alone = options;
    alone.check_endpoints = false;
    for (const RobotMotion& m : motions) {
      if (robotSegment(world, context, m.start, m.q_end, report, alone, near)) return true;
    }
    return false;
  }
  int n = 1;
  for (const RobotMotion& m : motions) {
    n = std::max(n, segmentSteps(world, m.start.robot, m.start.q, m.q_end, m.start.held, options.resolution));
  }
  if (!detail::coverOn(world)) {
    return forEachStepCoarseToFine(context, n, [&](int k) { return check_states(static_cast<double>(k) / n); });
  }
  thread_local std::vector<std::uint8_t> cleared;
  thread_local std::vector<RobotState> starts;  // `states` holds the last step checked, not the start
  thread_local std::vector<JointVector> ends;
  starts.clear();
  ends.clear();
  for (const RobotMotion& m : motions) {
    starts.push_back(m.start);
    ends.push_back(m.q_end);
  }
  detail::coverMotionSteps(world, context, starts, ends, options.scope, near, n, cleared);
  context.counters().cover_cleared += static_cast<std::uint64_t>(std::count(cleared.begin(), cleared.end(), 1));
  return forEachStepCoarseToFine(context, n, [&](int k) {
    return cleared[at(k)] == 0 && check_states(static_cast<double>(k) / n);
  });
}

bool gripperEntersContactBox(const CollisionWorld& world, CollisionContext& context, int robot, const JointVector& q0,
                             const JointVector& q1, const ObjectLayout& layout) {
  const RobotGeometry& rg = world.robot(robot);
  const SceneRobot& sr = *rg.robot;
  std::vector<Pose> frames(rg.bodies.size());
  auto framesAt = [&](double s) { bodyFrames(*rg.model, sr.X_WB, q0 + s * (q1 - q0), frames); };
  framesAt(0.0);
  const std::vector<Pose> frames0 = frames;
  for (int b = 0; b < static_cast<int>(rg.bodies.size()); ++b) {
    const BodyGeometry& body = rg.bodies[at(b)];
    if (!body.is_gripper) continue;
    const double L = bodyDisplacementBound(world, robot, b, q0, q1);
    const Vec3 p0 = frames0[at(b)].translation();
    for (int j = 0; j < layout.size(); ++j) {
      if (!layout.isPresent(j)) continue;
      const ObjectGeometry& object = world.object(j);
      const Pose& X_WO = layout.X_WO[at(j)];
      // Out of reach: every point of the body stays within extent of its frame origin, and the origin
      // moves at most L + 2 extent (a body point moves at most L; the turn of the body adds the rest).
      if ((X_WO.translation() - p0).norm() > 3.0 * body.extent + object.contact_half_extents.norm() + L) continue;
      double s = 0.0;
      for (;;) {
        framesAt(s);
        const double d = signedDistance(context, *body.shape, frames[at(b)] * body.X_FG, *object.contact_shape, X_WO);
        if (d < 0.0) return true;
        if (s >= 1.0 || L <= 0.0) break;
        s = std::min(1.0, s + std::max(d, kAdvanceFloor) / L);
      }
    }
  }
  return false;
}

}  // namespace dash
