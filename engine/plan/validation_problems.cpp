#include "engine/plan/validation_problems.h"

#include <algorithm>
#include <cmath>
#include <fcl/narrowphase/collision.h>
#include <tuple>

namespace dash::validation {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

bool isRobotSide(const CollisionElement& e) {
  return e.kind == CollisionElement::Kind::kRobotBody || e.kind == CollisionElement::Kind::kHeldObject;
}

/// Problems are grouped by who meets whom: robot, object, obstacle; bodies only count for self
/// collisions (otherwise one arm sliding along a box would give a problem per body in turn).
auto elementKey(const CollisionElement& e, bool with_body) {
  return std::make_tuple(static_cast<int>(e.kind), e.robot, with_body ? e.body : -1, e.index);
}

auto contactKey(const PairContact& c) {
  const ProblemKind kind = collisionKind(c.a, c.b);
  const bool bodies = kind == ProblemKind::kSelfCollision;
  return std::make_tuple(static_cast<int>(kind), elementKey(c.a, bodies), elementKey(c.b, bodies));
}

/// "ur5e_0.forearm", "obj_3 (held by ur5e_0)", "shelf_board_1", "obj_2".
std::string shortName(const CollisionElement& e, const Scene& scene) {
  switch (e.kind) {
    case CollisionElement::Kind::kRobotBody:
      return scene.robots[at(e.robot)].id + "." + scene.robots[at(e.robot)].model->bodies[at(e.body)].name;
    case CollisionElement::Kind::kHeldObject:
      return scene.objects[at(e.index)].id + " (held by " + scene.robots[at(e.robot)].id + ")";
    case CollisionElement::Kind::kObstacle:
      return scene.obstacles[at(e.index)].id;
    case CollisionElement::Kind::kObject:
      return scene.objects[at(e.index)].id;
    case CollisionElement::Kind::kNone:
      break;
  }
  return "";
}

std::string mm(double metres) { return formatNumber(metres * 1000.0, 3) + " mm"; }

std::string when(double t, double t_end) {
  return t == t_end ? "at t=" + formatNumber(t, 6) : "from t=" + formatNumber(t, 6) + " to t=" + formatNumber(t_end, 6);
}

ValidationProblem contactProblem(const Scene& scene, const ValidationOptions& options, const PairContact& c) {
  ValidationProblem p;
  p.kind = collisionKind(c.a, c.b);
  p.t = c.t_first;
  p.t_end = c.t_last;
  p.distance = c.distance;
  p.t_closest = c.t_closest;
  if (isRobotSide(c.a)) p.robot = scene.robots[at(c.a.robot)].id;
  for (const CollisionElement* e : {&c.a, &c.b}) {
    const bool is_object = e->kind == CollisionElement::Kind::kHeldObject || e->kind == CollisionElement::Kind::kObject;
    if (is_object && p.object.empty()) p.object = scene.objects[at(e->index)].id;
  }
  if (isRobotSide(c.b)) {
    p.other = c.b.robot == c.a.robot && c.b.kind == CollisionElement::Kind::kRobotBody
                  ? scene.robots[at(c.b.robot)].model->bodies[at(c.b.body)].name
                  : scene.robots[at(c.b.robot)].id;
  } else {
    p.other = shortName(c.b, scene);
  }
  if (c.possible) {
    // Conservative advancement reached its floor without proving the pair apart: no measured instant
    // was in contact, but the motion bound allows one between two of them.
    p.message = describe(c.a, scene) + " may touch " + describe(c.b, scene) + " " + when(p.t, p.t_end) +
                ": not certified at the " + mm(options.certify_floor) + " floor (closest measured " + mm(c.distance) +
                " at t=" + formatNumber(c.t_closest, 6) + "; the motion bound allows " + mm(c.bound) +
                "; clearance " + mm(options.clearance) + ")";
  } else if (c.distance < 0.0) {
    p.message = describe(c.a, scene) + " overlaps " + describe(c.b, scene) + " " + when(p.t, p.t_end) + ", " +
                mm(-c.distance) + " deep at t=" + formatNumber(c.t_closest, 6);
  } else {
    p.message = describe(c.a, scene) + " comes within " + mm(c.distance) + " of " + describe(c.b, scene) + " " +
                when(p.t, p.t_end) + " (closest at t=" + formatNumber(c.t_closest, 6) + "; clearance " +
                mm(options.clearance) + ")";
  }
  if (p.kind != ProblemKind::kSelfCollision && p.t != p.t_end) p.message += " (bodies as at the first contact)";
  return p;
}

}  // namespace

ProblemKind collisionKind(const CollisionElement& a, const CollisionElement& b) {
  using K = CollisionElement::Kind;
  if (a.kind == K::kHeldObject || b.kind == K::kHeldObject) return ProblemKind::kHeldObjectCollision;
  if (a.kind == K::kRobotBody && b.kind == K::kRobotBody) {
    return a.robot == b.robot ? ProblemKind::kSelfCollision : ProblemKind::kRobotRobotCollision;
  }
  if (a.kind == K::kObstacle || b.kind == K::kObstacle) {
    return a.kind == K::kObject || b.kind == K::kObject ? ProblemKind::kObjectObjectCollision
                                                        : ProblemKind::kRobotObstacleCollision;
  }
  if (a.kind == K::kObject && b.kind == K::kObject) return ProblemKind::kObjectObjectCollision;
  return ProblemKind::kRobotObjectCollision;
}

std::vector<ValidationProblem> restingObjectProblems(const CollisionWorld& world, const Timeline& timeline) {
  std::vector<ValidationProblem> problems;
  const fcl::CollisionRequestd request;
  const Scene& scene = world.scene();
  for (const Epoch& epoch : timeline.epochs) {
    const ObjectLayout& layout = epoch.layout;
    for (int j = 0; j < layout.size(); ++j) {
      if (!layout.isPresent(j)) continue;
      const Pose& X_j = layout.X_WO[at(j)];
      const Aabb box_j = boxAabb(X_j, world.object(j).contact_half_extents);
      for (int k = j + 1; k < layout.size(); ++k) {
        if (!layout.isPresent(k)) continue;
        const Pose& X_k = layout.X_WO[at(k)];
        if (!box_j.intersects(boxAabb(X_k, world.object(k).contact_half_extents))) continue;
        fcl::CollisionResultd result;
        if (fcl::collide(world.object(j).contact_shape.get(), X_j, world.object(k).contact_shape.get(), X_k, request,
                         result) == 0) {
          continue;
        }
        ValidationProblem p;
        p.kind = ProblemKind::kObjectObjectCollision;
        p.t = p.t_end = p.t_closest = epoch.t;
        p.object = scene.objects[at(j)].id;
        p.other = scene.objects[at(k)].id;
        p.message = describe(CollisionElement::object(j), scene) + " overlaps " +
                    describe(CollisionElement::object(k), scene) + " at t=" + formatNumber(epoch.t, 6);
        problems.push_back(std::move(p));
      }
    }
  }
  return problems;
}

void appendContactProblems(const Scene& scene, const ValidationOptions& options, std::vector<PairContact> contacts,
                           double join, std::vector<ValidationProblem>& problems) {
  std::stable_sort(contacts.begin(), contacts.end(), [](const PairContact& x, const PairContact& y) {
    return std::make_tuple(contactKey(x), x.t_first) < std::make_tuple(contactKey(y), y.t_first);
  });
  for (std::size_t i = 0; i < contacts.size();) {
    PairContact merged = contacts[i];
    std::size_t k = i + 1;
    for (; k < contacts.size() && contactKey(contacts[k]) == contactKey(contacts[i]); ++k) {
      if (contacts[k].t_first > merged.t_last + join) break;
      merged.t_last = std::max(merged.t_last, contacts[k].t_last);
      merged.possible = merged.possible && contacts[k].possible;
      merged.bound = std::min(merged.bound, contacts[k].bound);
      if (contacts[k].distance < merged.distance) {
        merged.distance = contacts[k].distance;
        merged.t_closest = contacts[k].t_closest;
      }
    }
    problems.push_back(contactProblem(scene, options, merged));
    i = k;
  }
}

void appendHandoverProblems(const Scene& scene, const ValidationOptions& options,
                            std::vector<HandoverMismatch> mismatches, std::vector<ValidationProblem>& problems) {
  auto key = [](const HandoverMismatch& m) { return std::make_tuple(m.object, m.epoch, m.robot, m.robot2); };
  std::stable_sort(mismatches.begin(), mismatches.end(), [&](const HandoverMismatch& x, const HandoverMismatch& y) {
    return std::make_tuple(key(x), x.t) < std::make_tuple(key(y), y.t);
  });
  for (std::size_t i = 0; i < mismatches.size();) {
    std::size_t k = i;
    double worst = 0.0;
    for (; k < mismatches.size() && key(mismatches[k]) == key(mismatches[i]); ++k) worst = std::max(worst, mismatches[k].distance);
    const HandoverMismatch& first = mismatches[i];
    ValidationProblem p;
    p.kind = ProblemKind::kHandover;
    p.t = first.t;
    p.t_end = mismatches[k - 1].t;
    p.t_closest = p.t;
    p.distance = worst;
    p.robot = scene.robots[at(first.robot)].id;
    p.object = scene.objects[at(first.object)].id;
    p.other = scene.robots[at(first.robot2)].id;
    p.message = p.object + " held by " + p.robot + " and " + p.other + ": the two attachments disagree by up to " +
                formatNumber(worst * 1000.0) + " mm " + when(p.t, p.t_end) + " (allowed " +
                formatNumber(options.handover_tolerance * 1000.0) + " mm)";
    problems.push_back(std::move(p));
    i = k;
  }
}

void fillClearances(const Scene& scene, const PairMinima& minima, ValidationReport& report) {
  report.pairs.clear();
  for (const auto& [id, m] : minima) {
    if (!std::isfinite(m.distance)) continue;  // never measured: its boxes kept it clear
    PairClearance c{.a = shortName(m.a, scene), .b = shortName(m.b, scene), .distance = m.distance, .t = m.t,
                    .contact_allowed = m.contact_meant};
    if (!m.contact_meant && m.distance < report.closest.distance) report.closest = c;
    report.pairs.push_back(std::move(c));
  }
  std::stable_sort(report.pairs.begin(), report.pairs.end(),
                   [](const PairClearance& x, const PairClearance& y) { return x.distance < y.distance; });
}

}  // namespace dash::validation
