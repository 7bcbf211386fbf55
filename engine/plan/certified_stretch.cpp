#include "engine/plan/certified_stretch.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "engine/collision/distance_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/plan/certified_geometry.h"
#include "engine/robots/kinematics.h"

namespace dash::validation {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// m: while the boxes of a pair are this much farther apart than the clearance, conservative
/// advancement steps on the boxes' distance without an exact one (cheaper than the shorter steps).
constexpr double kBoxStepMargin = 0.01;  // cmd_validate.cpp says "10 mm" when no pair came closer
/// Steps through a contact are this much finer than what the bound allows (depth accuracy).
constexpr double kContactRefinement = 4.0;

Aabb grown(const Aabb& box, double margin) { return Aabb(box.min().array() - margin, box.max().array() + margin); }

Aabb bodyBox(const BodyGeometry& g, const Pose& X_WF) {
  if (g.is_capsule) {
    const Vec3 p_a = X_WF * g.a;
    const Vec3 p_b = X_WF * g.b;
    return Aabb(p_a.cwiseMin(p_b).array() - g.radius, p_a.cwiseMax(p_b).array() + g.radius);
  }
  return boxAabb(X_WF * makePose(g.center), g.half_extents);
}

/// Held objects of an epoch, per robot.
HeldObject heldBy(const Epoch& epoch, int r) {
  for (std::size_t j = 0; j < epoch.objects.size(); ++j) {
    for (const Holder& h : epoch.objects[j].holders) {
      if (h.robot == r) return HeldObject{static_cast<int>(j), h.X_TO};
    }
  }
  return {};
}

/// The static things within the contact tolerance of object j resting at X_WO among `layout`.
void supportsAt(const CollisionWorld& world, CollisionContext& context, int j, const Pose& X_WO,
                const ObjectLayout& layout, std::vector<CollisionElement>& out) {
  const ObjectGeometry& g = world.object(j);
  const double reach = kObjectContactTolerance + kTouchTolerance;
  const Aabb box = grown(boxAabb(X_WO, g.half_extents), reach);
  auto add = [&](const CollisionElement& e) {
    if (std::find(out.begin(), out.end(), e) == out.end()) out.push_back(e);
  };
  for (std::size_t i = 0; i < world.obstacles().size(); ++i) {
    const ObstacleGeometry& o = world.obstacles()[i];
    if (box.intersects(o.aabb) && signedDistance(context, *g.shape, X_WO, *o.shape, o.X_WO) <= reach) {
      add(CollisionElement::obstacle(static_cast<int>(i)));
    }
  }
  for (int k = 0; k < layout.size(); ++k) {
    if (k == j || !layout.isPresent(k)) continue;
    const Pose& X_WK = layout.X_WO[at(k)];
    if (box.intersects(boxAabb(X_WK, world.object(k).half_extents)) &&
        signedDistance(context, *g.shape, X_WO, *world.object(k).shape, X_WK) <= reach) {
      add(CollisionElement::object(k));
    }
  }
}

/// The largest dyadic fraction in (u, u + step] with a denominator of about 2 / step: never past what
/// the step certifies, and shared by pairs that advance alike, so their poses are computed once.
double nextOnGrid(double u, double step) {
  const double scale = std::exp2(std::ceil(std::log2(2.0 / step)));
  const double next = std::floor((u + step) * scale) / scale;
  return next > u ? next : u + step;
}

/// One pair's minima in a total order (distance, then time, then a pair not in contact by design
/// first): the one kept does not depend on the order stretches are checked in, nor on the threads.
bool closer(const PairMinimum& x, const PairMinimum& y) {
  return std::make_tuple(x.distance, x.t, x.contact_meant) < std::make_tuple(y.distance, y.t, y.contact_meant);
}

}  // namespace

PairId pairId(const CollisionElement& a, const CollisionElement& b) {
  return {static_cast<int>(a.kind), a.robot, a.body, a.index, static_cast<int>(b.kind), b.robot, b.body, b.index};
}

void mergeMinima(PairMinima& into, const PairMinima& from) {
  for (const auto& [id, m] : from) {
    auto [it, inserted] = into.emplace(id, m);
    if (!inserted && closer(m, it->second)) it->second = m;
  }
}

Supports findSupports(const CollisionWorld& world, CollisionContext& context, const Timeline& timeline) {
  const auto& epochs = timeline.epochs;
  Supports supports(epochs.size(), std::vector<std::vector<CollisionElement>>(at(world.objectCount())));
  for (int j = 0; j < world.objectCount(); ++j) {
    for (std::size_t e = 0; e < epochs.size();) {
      if (!epochs[e].objects[at(j)].held()) {
        ++e;
        continue;
      }
      std::size_t end = e;  // one past the last epoch of the holding stretch
      while (end < epochs.size() && epochs[end].objects[at(j)].held()) ++end;
      std::vector<CollisionElement> found;
      if (e > 0) supportsAt(world, context, j, epochs[e - 1].objects[at(j)].X_WO, epochs[e - 1].layout, found);
      if (end < epochs.size()) supportsAt(world, context, j, epochs[end].objects[at(j)].X_WO, epochs[end].layout, found);
      for (std::size_t k = e; k < end; ++k) supports[k][at(j)] = found;
      e = end;
    }
  }
  return supports;
}

StretchChecker::StretchChecker(const CollisionWorld& world, const PlanMotion& motion, const Timeline& timeline,
                               const Supports& supports, const ValidationOptions& options)
    : world_(world), motion_(motion), timeline_(timeline), supports_(supports), options_(options), context_(world) {
  robots_.resize(at(world.robotCount()));
  poses_.resize(at(world.robotCount()));
  findGraspTargets();
}

void StretchChecker::findGraspTargets() {
  const auto& epochs = timeline_.epochs;
  const std::size_t robots = robots_.size();
  // What each robot holds in each epoch (-1: nothing; the first object found when it holds two).
  std::vector<std::vector<int>> held(epochs.size(), std::vector<int>(robots, -1));
  for (std::size_t e = 0; e < epochs.size(); ++e) {
    for (std::size_t j = 0; j < epochs[e].objects.size(); ++j) {
      for (const Holder& h : epochs[e].objects[j].holders) {
        if (held[e][at(h.robot)] < 0) held[e][at(h.robot)] = static_cast<int>(j);
      }
    }
  }
  grasp_targets_.assign(epochs.size(), std::vector<GraspTarget>(robots));
  for (std::size_t r = 0; r < robots; ++r) {
    // Only an empty hand has a target: a hand that holds something touches nothing else by design.
    int last = -1;
    for (std::size_t e = 0; e < epochs.size(); ++e) {
      if (held[e][r] < 0) grasp_targets_[e][r].last = last;
      if (held[e][r] >= 0) last = held[e][r];
    }
    int next = -1;
    for (std::size_t e = epochs.size(); e-- > 0;) {
      if (held[e][r] < 0) grasp_targets_[e][r].next = next;
      if (held[e][r] >= 0) next = held[e][r];
    }
  }
}

CollisionElement StretchChecker::element(int r, int part) const {
  const int bodies = static_cast<int>(world_.robot(r).bodies.size());
  return part < bodies ? CollisionElement::robotBody(r, part) : CollisionElement::heldObject(r, robots_[at(r)].held.object);
}

const StretchChecker::Posed& StretchChecker::pose(int r, double u) {
  Poses& poses = poses_[at(r)];
  if (const auto found = poses.index.find(u); found != poses.index.end()) return poses.pool[found->second];
  if (poses.used == poses.pool.size()) {
    const std::size_t bodies = world_.robot(r).bodies.size();
    Posed fresh;
    fresh.frames.assign(bodies, Pose::Identity());
    fresh.X_WG.assign(bodies, Pose::Identity());
    fresh.boxes.resize(bodies + 1);
    poses.pool.push_back(std::move(fresh));
  }
  poses.index.emplace(u, poses.used);
  Posed& p = poses.pool[poses.used++];
  const Robot& robot = robots_[at(r)];
  const RobotGeometry& rg = world_.robot(r);
  const JointVector q = robot.moving ? JointVector(robot.q0 + u * (robot.q1 - robot.q0)) : robot.q0;
  bodyFrames(*rg.model, rg.robot->X_WB, q, p.frames);
  for (std::size_t b = 0; b < rg.bodies.size(); ++b) {
    p.X_WG[b] = p.frames[b] * rg.bodies[b].X_FG;
    p.boxes[b] = bodyBox(rg.bodies[b], p.frames[b]);
  }
  if (robot.held.holding()) {
    p.X_WO = forwardKinematics(*rg.model, rg.robot->X_WB, q).X_WT * robot.held.X_TO;
    p.boxes.back() = boxAabb(p.X_WO, world_.object(robot.held.object).half_extents);
  }
  return p;
}

void StretchChecker::setUp(const Stretch& stretch) {
  stretch_ = stretch;
  const Epoch& epoch = timeline_.epochs[at(stretch.epoch)];
  for (int r = 0; r < world_.robotCount(); ++r) {
    Robot& robot = robots_[at(r)];
    robot.q0 = motion_.q(r, stretch.t0);
    robot.q1 = motion_.q(r, stretch.t1);
    robot.held = heldBy(epoch, r);
    robot.moving = robot.q0 != robot.q1;
    robot.checked = robot.moving || !stretch.same_epoch_as_before;
    const RobotGeometry& rg = world_.robot(r);
    const std::size_t bodies = rg.bodies.size();
    robot.rate.assign(bodies + 1, 0.0);
    if (robot.moving) {
      for (std::size_t b = 0; b < bodies; ++b) {
        robot.rate[b] = bodyDisplacementBound(world_, r, static_cast<int>(b), robot.q0, robot.q1);
      }
      robot.rate[bodies] = heldDisplacementBound(world_, r, robot.q0, robot.q1, robot.held);
    }
    poses_[at(r)].index.clear();
    poses_[at(r)].used = 0;
    const std::vector<Aabb>& start = pose(r, 0.0).boxes;
    const Posed& end = pose(r, robot.moving ? 1.0 : 0.0);
    robot.swept.resize(bodies + 1);
    robot.swept_all.setEmpty();
    for (std::size_t p = 0; p <= bodies; ++p) {
      if (p == bodies && !robot.held.holding()) {
        robot.swept[p].setEmpty();
        continue;
      }
      robot.swept[p] = grown(start[p].merged(end.boxes[p]), 0.5 * robot.rate[p]);
      robot.swept_all.extend(robot.swept[p]);
    }
  }
}

bool StretchChecker::isSupport(int object, const CollisionElement& thing) const {
  const auto& found = supports_[at(stretch_.epoch)][at(object)];
  return std::find(found.begin(), found.end(), thing) != found.end();
}

void StretchChecker::addPair(int ra, int pa, const CollisionElement& b, const Aabb& b_box, int rb, int pb,
                             bool contact_meant) {
  // Pairs whose swept boxes come within kBoxStepMargin of the clearance are measured, so that the
  // report's smallest clearance is true up to that margin ("over 10 mm" otherwise).
  const double margin = (contact_meant ? 0.0 : options_.clearance) + kBoxStepMargin;
  if (!grown(robots_[at(ra)].swept[at(pa)], margin).intersects(b_box)) return;
  Pair pair{.ra = ra, .pa = pa, .b = b, .rb = rb, .pb = pb, .contact_meant = contact_meant};
  pair.rate = robots_[at(ra)].rate[at(pa)] + (rb >= 0 ? robots_[at(rb)].rate[at(pb)] : 0.0);
  pairs_.push_back(pair);
}

void StretchChecker::collectPairs(int r) {
  const Robot& robot = robots_[at(r)];
  const RobotGeometry& rg = world_.robot(r);
  const int bodies = static_cast<int>(rg.bodies.size());
  const double c = options_.clearance + kBoxStepMargin;  // the widest margin addPair uses
  const Epoch& epoch = timeline_.epochs[at(stretch_.epoch)];
  const ObjectLayout& layout = epoch.layout;
  for (const int i : rg.nearby_obstacles) {
    const ObstacleGeometry& o = world_.obstacles()[at(i)];
    if (!grown(robot.swept_all, c).intersects(o.aabb)) continue;
    for (int b = 0; b < bodies; ++b) addPair(r, b, CollisionElement::obstacle(i), o.aabb, -1, -1, false);
  }
  for (int j = 0; j < layout.size(); ++j) {
    if (!layout.isPresent(j)) continue;
    const Aabb box = boxAabb(layout.X_WO[at(j)], world_.object(j).half_extents);
    if (!grown(robot.swept_all, c).intersects(box)) continue;
    // A gripper touches a resting object only as it is about to grasp it or has just let it go.
    const bool target = holdsAdjacent(r, j);
    for (int b = 0; b < bodies; ++b) {
      addPair(r, b, CollisionElement::object(j), box, -1, -1, target && rg.bodies[at(b)].is_gripper);
    }
    if (robot.held.holding()) {
      const CollisionElement thing = CollisionElement::object(j);
      addPair(r, bodies, thing, box, -1, -1, isSupport(robot.held.object, thing));
    }
  }
  for (const auto& [b1, b2] : rg.model->self_collision_pairs) {
    addPair(r, b1, CollisionElement::robotBody(r, b2), grown(robot.swept[at(b2)], 0.0), r, b2, false);
  }
  if (!robot.held.holding()) return;
  for (std::size_t i = 0; i < world_.obstacles().size(); ++i) {
    const CollisionElement thing = CollisionElement::obstacle(static_cast<int>(i));
    addPair(r, bodies, thing, world_.obstacles()[i].aabb, -1, -1, isSupport(robot.held.object, thing));
  }
  for (const int b : rg.non_gripper_bodies) addPair(r, bodies, CollisionElement::robotBody(r, b), robot.swept[at(b)], r, b, false);
}

void StretchChecker::collectRobotPairs(int r, int s) {
  const Robot& a = robots_[at(r)];
  const Robot& b = robots_[at(s)];
  if (!grown(a.swept_all, options_.clearance + kBoxStepMargin).intersects(b.swept_all)) return;
  const int bodies_a = static_cast<int>(world_.robot(r).bodies.size());
  const int bodies_b = static_cast<int>(world_.robot(s).bodies.size());
  const bool same_object = a.held.holding() && a.held.object == b.held.object;  // a handover
  const int parts_a = bodies_a + (a.held.holding() ? 1 : 0);
  const int parts_b = bodies_b + (b.held.holding() ? 1 : 0);
  for (int pa = 0; pa < parts_a; ++pa) {
    for (int pb = 0; pb < parts_b; ++pb) {
      const bool held_a = pa == bodies_a;
      const bool held_b = pb == bodies_b;
      if (same_object && ((held_a && held_b) || (held_a && world_.robot(s).bodies[at(pb)].is_gripper) ||
                          (held_b && world_.robot(r).bodies[at(pa)].is_gripper))) {
        continue;
      }
      // A gripper about to take an object over from another robot, or that just handed it over,
      // touches it: contact meant, as with a resting object.
      const bool taking_over = (held_b && world_.robot(r).bodies[at(pa)].is_gripper && holdsAdjacent(r, b.held.object)) ||
                               (held_a && world_.robot(s).bodies[at(pb)].is_gripper && holdsAdjacent(s, a.held.object));
      addPair(r, pa, element(s, pb), b.swept[at(pb)], s, pb, taking_over);
    }
  }
}

bool StretchChecker::holdsAdjacent(int r, int object) const {
  const GraspTarget& g = grasp_targets_[at(stretch_.epoch)][at(r)];
  return g.last == object || g.next == object;
}

double StretchChecker::distance(const Pair& pair, double u, bool& exact) {
  const Posed& pa = pose(pair.ra, u);
  const RobotGeometry& ga = world_.robot(pair.ra);
  const bool held_a = pair.pa == static_cast<int>(ga.bodies.size());
  const int held_object = robots_[at(pair.ra)].held.object;
  // Side b's shape, pose and box.
  const fcl::CollisionGeometry<double>* shape_b = nullptr;
  Pose X_b = Pose::Identity();
  Aabb box_b;
  if (pair.rb >= 0) {
    const Posed& pb = pose(pair.rb, u);
    const RobotGeometry& gb = world_.robot(pair.rb);
    if (pair.pb < static_cast<int>(gb.bodies.size())) {
      shape_b = gb.bodies[at(pair.pb)].shape.get();
      X_b = pb.X_WG[at(pair.pb)];
    } else {
      shape_b = world_.object(robots_[at(pair.rb)].held.object).shape.get();
      X_b = pb.X_WO;
    }
    box_b = pb.boxes[at(pair.pb)];
  } else if (pair.b.kind == CollisionElement::Kind::kObstacle) {
    const ObstacleGeometry& o = world_.obstacles()[at(pair.b.index)];
    shape_b = o.shape.get();
    X_b = o.X_WO;
    box_b = o.aabb;
  } else {
    const ObjectGeometry& g = world_.object(pair.b.index);
    X_b = timeline_.epochs[at(stretch_.epoch)].layout.X_WO[at(pair.b.index)];
    // A gripper against a resting object: contact meant, the contact box.
    shape_b = pair.contact_meant && !held_a ? g.contact_shape.get() : g.shape.get();
    box_b = boxAabb(X_b, g.half_extents);
  }
  const double lower = pa.boxes[at(pair.pa)].exteriorDistance(box_b);
  // The boxes' distance is a lower bound: enough to step on while it is well above the clearance.
  const double clearance = pair.contact_meant ? 0.0 : options_.clearance;
  // Measured whenever the boxes are within the margin, so that the report's minima are true to it.
  exact = lower <= clearance + kBoxStepMargin;
  if (!exact) return lower;
  ++evaluations_;
  if (!held_a) return signedDistance(context_, *ga.bodies[at(pair.pa)].shape, pa.X_WG[at(pair.pa)], *shape_b, X_b);
  if (pair.contact_meant && pair.rb < 0) {  // on what it rests (a gripper taking it over: exact)
    const PosedShape held = heldStaticShape(world_, held_object, pa.X_WO);
    return signedDistance(context_, *held.shape, held.X_WS, *shape_b, X_b);
  }
  return signedDistance(context_, *world_.object(held_object).shape, pa.X_WO, *shape_b, X_b);
}

void StretchChecker::advance(const Pair& pair, std::vector<PairContact>& contacts, PairMinima& minima) {
  const double c = pair.contact_meant ? 0.0 : options_.clearance;
  const double span = stretch_.t1 - stretch_.t0;
  const double floor_u = pair.rate > 0.0 ? options_.certify_floor / pair.rate : 1.0;
  PairMinimum& minimum = minima.try_emplace(pairId(element(pair.ra, pair.pa), pair.b),
                                            PairMinimum{element(pair.ra, pair.pa), pair.b, pair.contact_meant,
                                                        std::numeric_limits<double>::infinity(), 0.0})
                             .first->second;
  PairContact* open = nullptr;  // only this pair appends to `contacts` while it is open
  // Extends the open contact to [.., t_to], or opens one at t_from.
  auto note = [&](double u_from, double t_from, double t_to, double d, double t_d, bool possible, double bound) {
    if (open == nullptr) {
      contacts.push_back({element(pair.ra, pair.pa), pair.b, t_from, t_to, d, t_d, u_from == 0.0, false, possible, bound});
      open = &contacts.back();
      return;
    }
    open->t_last = std::max(open->t_last, t_to);
    if (d < open->distance) {
      open->distance = d;
      open->t_closest = t_d;
    }
    open->possible = open->possible && possible;
    open->bound = std::min(open->bound, bound);
  };
  // The previous instant, when its distance alone did not prove the step from it clear (a step at the
  // floor, or one from a contact): the step is then bounded from both ends.
  bool pending = false;
  double u_prev = 0.0;
  double t_prev = 0.0;
  double d_prev = 0.0;
  double u = 0.0;
  for (;;) {
    // Past `enough`, the rest of the stretch is certified clear: no need for the exact distance.
    const double enough = c + pair.rate * (1.0 - u);
    bool exact = false;
    const double d = distance(pair, u, exact);
    const double t = stretch_.t0 + u * span;
    if (exact) {
      const PairMinimum measured{minimum.a, minimum.b, pair.contact_meant, d, t};
      if (closer(measured, minimum)) minimum = measured;
    }
    const bool in_contact = d < c - kTouchTolerance;
    if (pending) {
      // Over [u_prev, u] the distance at s is at least d_prev - rate (s - u_prev) and d - rate (u - s).
      const double lower = 0.5 * (d_prev + d - pair.rate * (u - u_prev));
      if (lower < c - kTouchTolerance) {
        note(u_prev, t_prev, t, std::min(d_prev, d), d < d_prev ? t : t_prev, true, lower);
      } else {
        open = nullptr;  // certified apart over the whole step
      }
      pending = false;
    }
    if (in_contact) note(u, t, t, d, t, false, d);
    if (u >= 1.0) {
      if (open != nullptr) open->to_end = true;
      break;
    }
    if (pair.rate <= 0.0 && open != nullptr) {  // holding still: so for the whole stretch
      open->t_last = stretch_.t1;
      open->to_end = true;
    }
    if (d > enough || pair.rate <= 0.0) break;
    // Clear: certified until the bound reaches the clearance. In contact: certified in contact until
    // the bound could lift it, but stepped 4 times finer so that the deepest point is found closely.
    // Never finer than the floor.
    const double step = std::max(in_contact ? (c - d) / (kContactRefinement * pair.rate) : (d - c) / pair.rate, floor_u);
    const double next = u + step >= 1.0 ? 1.0 : nextOnGrid(u, step);
    // A pair not in contact by design that its distance here does not keep apart over the step (the
    // floor): the next instant bounds the step from its end too, and what is still not certified is a
    // possible contact. Pairs in contact by design keep the floor's resolution.
    const bool certified = d - pair.rate * (next - u) >= c - kTouchTolerance;
    pending = in_contact || (!certified && !pair.contact_meant);
    if (!pending) open = nullptr;
    if (next >= 1.0 && !pending) break;
    u_prev = u;
    t_prev = t;
    d_prev = d;
    u = next;
  }
}

void StretchChecker::check(const Stretch& stretch, std::vector<PairContact>& contacts, PairMinima& minima) {
  setUp(stretch);
  pairs_.clear();
  const int robots = world_.robotCount();
  for (int r = 0; r < robots; ++r) {
    if (robots_[at(r)].checked) collectPairs(r);
  }
  for (int r = 0; r < robots; ++r) {
    for (int s = r + 1; s < robots; ++s) {
      if (robots_[at(r)].checked || robots_[at(s)].checked) collectRobotPairs(r, s);
    }
  }
  for (const Pair& pair : pairs_) advance(pair, contacts, minima);
}

}  // namespace dash::validation
