#include "engine/plan/validation_geometry.h"

#include <algorithm>
#include <fcl/narrowphase/collision.h>
#include <tuple>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_queries.h"
#include "engine/collision/collision_world.h"
#include "engine/collision/segment_queries.h"
#include "engine/plan/validation_workers.h"

namespace dash::validation {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Below this many samples per thread, more threads cost more than they save.
constexpr std::size_t kMinSamplesPerThread = 256;
/// Joint limits keep a segment's samples in the thousands; a plan far outside them (reported as
/// joint_limit) must not exhaust memory.
constexpr int kMaxStepsPerInterval = 100000;

/// A stretch between consecutive point or event times: every robot moves on one straight segment.
struct Interval {
  double t0 = 0.0;
  double t1 = 0.0;
  int epoch = 0;
  std::vector<std::uint8_t> included;  ///< robots checked at interior samples: moving, or near one that moves
};

struct Sample {
  double t = 0.0;
  int epoch = 0;
  int interval = -1;  ///< the interval of an interior sample; -1 for a full sample
  bool full = true;   ///< every robot is checked (point and event times)
};

/// One pair found colliding (or one object's attachments disagreeing) at one sample.
struct Hit {
  std::size_t sample = 0;
  ProblemKind kind = ProblemKind::kSelfCollision;
  CollisionElement a;
  CollisionElement b;
  double value = 0.0;  ///< handover: how far the attachments disagree
};

/// Hits are grouped into problems by who meets whom: robot, object, obstacle; bodies only count for
/// self collisions (otherwise one arm sliding along a box would give a problem per body in turn).
auto elementKey(const CollisionElement& e, bool with_body) {
  return std::make_tuple(static_cast<int>(e.kind), e.robot, with_body ? e.body : -1, e.index);
}
auto hitKey(const Hit& h) {
  const bool bodies = h.kind == ProblemKind::kSelfCollision;
  return std::make_tuple(static_cast<int>(h.kind), elementKey(h.a, bodies), elementKey(h.b, bodies));
}

bool isRobotSide(const CollisionElement& e) {
  return e.kind == CollisionElement::Kind::kRobotBody || e.kind == CollisionElement::Kind::kHeldObject;
}

ProblemKind collisionKind(const CollisionReport& rep) {
  using K = CollisionElement::Kind;
  if (rep.a.kind == K::kHeldObject || rep.b.kind == K::kHeldObject) return ProblemKind::kHeldObjectCollision;
  if (rep.a.kind == K::kRobotBody && rep.b.kind == K::kRobotBody) {
    return rep.a.robot == rep.b.robot ? ProblemKind::kSelfCollision : ProblemKind::kRobotRobotCollision;
  }
  if (rep.a.kind == K::kObstacle || rep.b.kind == K::kObstacle) {
    return rep.a.kind == K::kObject || rep.b.kind == K::kObject ? ProblemKind::kObjectObjectCollision
                                                                  : ProblemKind::kRobotObstacleCollision;
  }
  if (rep.a.kind == K::kObject && rep.b.kind == K::kObject) return ProblemKind::kObjectObjectCollision;
  return ProblemKind::kRobotObjectCollision;
}

class GeometryChecker {
 public:
  GeometryChecker(const Plan& plan, const PlanMotion& motion, const Timeline& timeline, const ValidationOptions& options)
      : scene_(motion.scene()), motion_(motion), timeline_(timeline), options_(options), world_(scene_, {.cover = false}) {
    inflateReach(plan);
    buildSamples();
  }

  void run(ValidationReport& report) {
    std::vector<Hit> hits = sampleAll();
    checkRestingObjects(hits);
    appendProblems(std::move(hits), report);
    report.samples = samples_.size();
  }

 private:
  /// Each robot's reach grown by the largest object it ever grasps, as placed by its X_TO.
  void inflateReach(const Plan& plan) {
    for (int r = 0; r < world_.robotCount(); ++r) reach_.push_back(world_.robot(r).reach);
    for (const PlanEvent& e : plan.events) {
      if (e.type != PlanEvent::Type::kGrasp) continue;
      const int r = scene_.robotIndex(e.robot);
      const int j = scene_.objectIndex(e.object);
      if (r < 0 || j < 0) continue;
      const double extent = e.X_TO.translation().norm() + 0.5 * scene_.objects[at(j)].shape.size.norm();
      Aabb& box = reach_[at(r)];
      box = Aabb(box.min().array() - extent, box.max().array() + extent);
    }
  }

  HeldObject heldBy(const Epoch& epoch, int r) const {
    for (std::size_t j = 0; j < epoch.objects.size(); ++j) {
      for (const Holder& h : epoch.objects[j].holders) {
        if (h.robot == r) return HeldObject{static_cast<int>(j), h.X_TO};
      }
    }
    return {};
  }

  void buildSamples() {
    std::vector<double> times{0.0};
    for (int r = 0; r < motion_.robotCount(); ++r) {
      if (const RobotTrajectory* traj = motion_.trajectory(r)) {
        for (const TrajectoryPoint& p : traj->points) times.push_back(p.t);
      }
    }
    for (const Epoch& e : timeline_.epochs) times.push_back(e.t);
    std::erase_if(times, [](double t) { return !(t >= 0.0); });  // malformed plans built in code
    std::sort(times.begin(), times.end());
    times.erase(std::unique(times.begin(), times.end()), times.end());

    const int robots = motion_.robotCount();
    for (std::size_t k = 0; k < times.size(); ++k) {
      const double t0 = times[k];
      const int epoch = timeline_.indexAt(t0);
      // At an event time, first the state just before the events (the limit from the left).
      if (epoch > 0 && timeline_.epochs[at(epoch)].t == t0) samples_.push_back({t0, epoch - 1, -1, true});
      samples_.push_back({t0, epoch, -1, true});
      if (k + 1 == times.size()) break;
      const double t1 = times[k + 1];
      Interval interval{t0, t1, epoch, std::vector<std::uint8_t>(at(robots), 0)};
      int steps = 1;
      std::vector<std::uint8_t> moving(at(robots), 0);
      for (int r = 0; r < robots; ++r) {
        if (motion_.trajectory(r) == nullptr) continue;
        const JointVector q0 = motion_.q(r, t0);
        const JointVector q1 = motion_.q(r, t1);
        if (q0 == q1) continue;
        moving[at(r)] = 1;
        const HeldObject held = heldBy(timeline_.epochs[at(epoch)], r);
        steps = std::clamp(segmentSteps(world_, r, q0, q1, held, options_.max_step), steps, kMaxStepsPerInterval);
      }
      for (int r = 0; r < robots; ++r) {
        for (int m = 0; m < robots && interval.included[at(r)] == 0; ++m) {
          if (moving[at(m)] != 0 && reach_[at(r)].intersects(reach_[at(m)])) interval.included[at(r)] = 1;
        }
      }
      const int index = static_cast<int>(intervals_.size());
      intervals_.push_back(std::move(interval));
      for (int s = 1; s < steps; ++s) {
        samples_.push_back({t0 + (t1 - t0) * static_cast<double>(s) / static_cast<double>(steps), epoch, index, false});
      }
    }
  }

  bool checked(const Sample& s, int r) const {
    return s.full || intervals_[at(s.interval)].included[at(r)] != 0;
  }

  std::vector<Hit> sampleAll() {
    const std::size_t threads = workerCount(options_.threads, samples_.size(), kMinSamplesPerThread);
    std::vector<std::vector<Hit>> found(threads);
    auto work = [&](std::size_t w) {
      CollisionContext context(world_);
      const std::size_t begin = samples_.size() * w / threads;
      const std::size_t end = samples_.size() * (w + 1) / threads;
      for (std::size_t i = begin; i < end; ++i) checkSample(context, i, found[w]);
    };
    runWorkers(threads, work);
    std::vector<Hit> hits;
    for (auto& part : found) hits.insert(hits.end(), part.begin(), part.end());
    return hits;
  }

  void checkSample(CollisionContext& context, std::size_t index, std::vector<Hit>& hits) const {
    const Sample& s = samples_[index];
    const Epoch& epoch = timeline_.epochs[at(s.epoch)];
    checkHandovers(epoch, s, index, hits);
    if (!options_.check_geometry) return;
    std::vector<RobotState> states;
    for (int r = 0; r < motion_.robotCount(); ++r) {
      if (checked(s, r)) states.push_back({r, motion_.q(r, s.t), heldBy(epoch, r)});
    }
    if (!robotsInCollision(world_, context, states, epoch.layout)) return;
    // Something collides: find every pair, not only the first. Per robot, static then objects; then
    // robot pairs among those with no static hit (a static hit would mask the pair in the query).
    auto record = [&](const CollisionReport& rep) { hits.push_back({index, collisionKind(rep), rep.a, rep.b, 0.0}); };
    std::vector<std::uint8_t> static_hit(states.size(), 0);
    std::vector<Aabb> boxes(states.size());
    for (std::size_t i = 0; i < states.size(); ++i) {
      CollisionReport rep;
      if (robotInCollision(world_, context, states[i], epoch.layout, &rep, CheckScope::kStaticOnly)) {
        static_hit[i] = 1;
        record(rep);
      }
      if (robotInCollision(world_, context, states[i], epoch.layout, &rep, CheckScope::kObjectsOnly)) record(rep);
      const auto& posed = context.scratch().robots[at(states[i].robot)];
      boxes[i] = posed.aabb;
      if (posed.held_object >= 0) boxes[i].extend(posed.held_aabb);
    }
    for (std::size_t i = 0; i < states.size(); ++i) {
      for (std::size_t k = i + 1; k < states.size(); ++k) {
        if (static_hit[i] != 0 || static_hit[k] != 0 || !boxes[i].intersects(boxes[k])) continue;
        const RobotState pair[2] = {states[i], states[k]};
        CollisionReport rep;
        if (robotsInCollision(world_, context, pair, epoch.layout, &rep, CheckScope::kStaticOnly)) record(rep);
      }
    }
  }

  /// While two robots hold one object, both attachments must put it at the same place.
  void checkHandovers(const Epoch& epoch, const Sample& s, std::size_t index, std::vector<Hit>& hits) const {
    for (std::size_t j = 0; j < epoch.objects.size(); ++j) {
      const auto& holders = epoch.objects[j].holders;
      if (holders.size() < 2) continue;
      const Pose X_1 = motion_.tcp(holders[0].robot, s.t) * holders[0].X_TO;
      const Pose X_2 = motion_.tcp(holders[1].robot, s.t) * holders[1].X_TO;
      const double d = translationDistance(X_1, X_2);
      if (d > options_.handover_tolerance) {
        hits.push_back({index, ProblemKind::kHandover, CollisionElement::heldObject(holders[0].robot, static_cast<int>(j)),
                        CollisionElement::heldObject(holders[1].robot, static_cast<int>(j)), d});
      }
    }
  }

  /// Resting objects only move at events, so each epoch's layout is checked once: no two overlap.
  void checkRestingObjects(std::vector<Hit>& hits) const {
    if (!options_.check_geometry) return;
    const fcl::CollisionRequestd request;
    for (std::size_t e = 0; e < timeline_.epochs.size(); ++e) {
      const ObjectLayout& layout = timeline_.epochs[e].layout;
      // The first sample of the epoch stands for it.
      const auto first = std::find_if(samples_.begin(), samples_.end(), [&](const Sample& s) { return s.epoch == static_cast<int>(e); });
      if (first == samples_.end()) continue;
      for (int j = 0; j < layout.size(); ++j) {
        if (!layout.isPresent(j)) continue;
        const Pose& X_j = layout.X_WO[at(j)];
        const Aabb box_j = boxAabb(X_j, world_.object(j).contact_half_extents);
        for (int k = j + 1; k < layout.size(); ++k) {
          if (!layout.isPresent(k)) continue;
          const Pose& X_k = layout.X_WO[at(k)];
          if (!box_j.intersects(boxAabb(X_k, world_.object(k).contact_half_extents))) continue;
          fcl::CollisionResultd result;
          if (fcl::collide(world_.object(j).contact_shape.get(), X_j, world_.object(k).contact_shape.get(), X_k, request,
                           result) > 0) {
            hits.push_back({static_cast<std::size_t>(first - samples_.begin()), ProblemKind::kObjectObjectCollision,
                            CollisionElement::object(j), CollisionElement::object(k), 0.0});
          }
        }
      }
    }
  }

  /// Whether the pair of `hit` was looked at in sample s (so its absence there means it was apart).
  bool looked(const Hit& hit, std::size_t s) const {
    const Sample& sample = samples_[s];
    if (hit.kind == ProblemKind::kHandover) {
      return timeline_.epochs[at(sample.epoch)].objects[at(hit.a.index)].holders.size() >= 2;
    }
    if (hit.kind == ProblemKind::kObjectObjectCollision && !isRobotSide(hit.a)) {
      return s == 0 || samples_[s - 1].epoch != sample.epoch;
    }
    for (const CollisionElement* e : {&hit.a, &hit.b}) {
      if (isRobotSide(*e) && !checked(sample, e->robot)) return false;
    }
    return true;
  }

  std::string id(const CollisionElement& e) const {
    switch (e.kind) {
      case CollisionElement::Kind::kRobotBody:
        return scene_.robots[at(e.robot)].model->bodies[at(e.body)].name;
      case CollisionElement::Kind::kHeldObject:
      case CollisionElement::Kind::kObject:
        return scene_.objects[at(e.index)].id;
      case CollisionElement::Kind::kObstacle:
        return scene_.obstacles[at(e.index)].id;
      case CollisionElement::Kind::kNone:
        break;
    }
    return "";
  }

  ValidationProblem problemFor(const Hit& first, const Hit& last, double worst) const {
    ValidationProblem p;
    p.kind = first.kind;
    p.t = samples_[first.sample].t;
    p.t_end = samples_[last.sample].t;
    const CollisionElement& a = first.a;
    const CollisionElement& b = first.b;
    if (isRobotSide(a)) p.robot = scene_.robots[at(a.robot)].id;
    for (const CollisionElement* e : {&a, &b}) {
      const bool is_object = e->kind == CollisionElement::Kind::kHeldObject || e->kind == CollisionElement::Kind::kObject;
      if (is_object && p.object.empty()) p.object = scene_.objects[at(e->index)].id;
    }
    if (b.kind == CollisionElement::Kind::kRobotBody || b.kind == CollisionElement::Kind::kHeldObject) {
      p.other = b.robot == a.robot ? id(b) : scene_.robots[at(b.robot)].id;
    } else {
      p.other = id(b);
    }
    const std::string when = p.t == p.t_end ? "at t=" + formatNumber(p.t, 6)
                                            : "from t=" + formatNumber(p.t, 6) + " to t=" + formatNumber(p.t_end, 6);
    if (p.kind == ProblemKind::kHandover) {
      p.message = p.object + " held by " + p.robot + " and " + p.other + ": the two attachments disagree by up to " +
                  formatNumber(worst * 1000.0) + " mm " + when + " (allowed " +
                  formatNumber(options_.handover_tolerance * 1000.0) + " mm)";
    } else {
      p.message = describe(a, scene_) + " overlaps " + describe(b, scene_) + " " + when;
      if (p.kind != ProblemKind::kSelfCollision && first.sample != last.sample) p.message += " (bodies as at the first contact)";
    }
    return p;
  }

  /// One problem per pair and stretch of samples in which the pair collided whenever it was looked at.
  void appendProblems(std::vector<Hit> hits, ValidationReport& report) const {
    std::stable_sort(hits.begin(), hits.end(), [](const Hit& x, const Hit& y) {
      return std::make_tuple(hitKey(x), x.sample) < std::make_tuple(hitKey(y), y.sample);
    });
    for (std::size_t i = 0; i < hits.size();) {
      std::size_t last = i;
      double worst = hits[i].value;
      std::size_t k = i + 1;
      for (; k < hits.size() && hitKey(hits[k]) == hitKey(hits[i]); ++k) {
        bool apart_between = false;
        for (std::size_t s = hits[last].sample + 1; s < hits[k].sample && !apart_between; ++s) {
          apart_between = looked(hits[i], s);
        }
        if (apart_between) break;
        if (hits[k].sample != hits[last].sample) last = k;
        worst = std::max(worst, hits[k].value);
      }
      report.problems.push_back(problemFor(hits[i], hits[last], worst));
      i = k;
    }
  }

  const Scene& scene_;
  const PlanMotion& motion_;
  const Timeline& timeline_;
  const ValidationOptions& options_;
  CollisionWorld world_;
  std::vector<Aabb> reach_;
  std::vector<Interval> intervals_;
  std::vector<Sample> samples_;
};

}  // namespace

void checkGeometry(const Plan& plan, const PlanMotion& motion, const Timeline& timeline,
                   const ValidationOptions& options, ValidationReport& report) {
  GeometryChecker checker(plan, motion, timeline, options);
  checker.run(report);
}

}  // namespace dash::validation
