#include "engine/plan/certified_geometry.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <tuple>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/collision/segment_queries.h"
#include "engine/plan/certified_stretch.h"
#include "engine/plan/validation_problems.h"
#include "engine/plan/validation_workers.h"

namespace dash::validation {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Below this many stretches per thread, more threads cost more than they save.
constexpr std::size_t kMinStretchesPerThread = 64;
/// Handover agreement samples per stretch at most (joint limits keep real plans far below).
constexpr int kMaxHandoverSteps = 100000;
/// s: stretches of contact closer than this in time are one problem.
constexpr double kJoinTolerance = 1e-9;

std::vector<Stretch> buildStretches(const Plan& plan, const PlanMotion& motion, const Timeline& timeline) {
  std::vector<double> times{0.0};
  for (int r = 0; r < motion.robotCount(); ++r) {
    if (const RobotTrajectory* traj = motion.trajectory(r)) {
      for (const TrajectoryPoint& p : traj->points) times.push_back(p.t);
    }
  }
  for (const Epoch& e : timeline.epochs) times.push_back(e.t);
  times.push_back(plan.lastTime());
  std::erase_if(times, [](double t) { return !(t >= 0.0) || !std::isfinite(t); });  // malformed plans built in code
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  std::vector<Stretch> stretches;
  for (std::size_t k = 0; k < times.size(); ++k) {
    const double t0 = times[k];
    // A zero-length stretch at the end checks the final state (and a plan with a single instant).
    const double t1 = k + 1 < times.size() ? times[k + 1] : t0;
    const int epoch = timeline.indexAt(t0);
    const bool same = !stretches.empty() && stretches.back().epoch == epoch;
    if (k + 1 == times.size() && same) break;  // the last stretch already ends there
    stretches.push_back({t0, t1, epoch, same});
  }
  return stretches;
}

/// While two robots hold one object, both attachments put it at the same place (sampled every
/// max_step of motion: a tolerance check, not a contact).
void checkHandovers(const CollisionWorld& world, const PlanMotion& motion, const Timeline& timeline,
                    const ValidationOptions& options, const Stretch& stretch, std::vector<HandoverMismatch>& out) {
  const Epoch& epoch = timeline.epochs[at(stretch.epoch)];
  for (std::size_t j = 0; j < epoch.objects.size(); ++j) {
    const auto& holders = epoch.objects[j].holders;
    if (holders.size() < 2) continue;
    int steps = 1;
    for (int h = 0; h < 2; ++h) {
      const int r = holders[at(h)].robot;
      const HeldObject held{static_cast<int>(j), holders[at(h)].X_TO};
      steps = std::clamp(segmentSteps(world, r, motion.q(r, stretch.t0), motion.q(r, stretch.t1), held, options.max_step),
                         steps, kMaxHandoverSteps);
    }
    for (int s = 0; s <= steps; ++s) {
      const double t = stretch.t0 + (stretch.t1 - stretch.t0) * static_cast<double>(s) / static_cast<double>(steps);
      const double d = translationDistance(motion.tcp(holders[0].robot, t) * holders[0].X_TO,
                                           motion.tcp(holders[1].robot, t) * holders[1].X_TO);
      if (d > options.handover_tolerance) {
        out.push_back({static_cast<int>(j), holders[0].robot, holders[1].robot, stretch.epoch, t, d});
      }
    }
  }
}

}  // namespace

void checkGeometryCertified(const Plan& plan, const PlanMotion& motion, const Timeline& timeline,
                            const ValidationOptions& options, ValidationReport& report) {
  const Scene& scene = motion.scene();
  const CollisionWorld world(scene, {.cover = false});  // exact geometry only (collision_world.h)
  const std::vector<Stretch> stretches = buildStretches(plan, motion, timeline);
  CollisionContext context(world);
  const Supports supports = findSupports(world, context, timeline);

  const std::size_t threads = workerCount(options.threads, stretches.size(), kMinStretchesPerThread);
  // What one worker found, with where each of its stretches' findings end (its k-th stretch is
  // stretches[w + k * threads]), so that the findings can be put back in stretch order.
  struct Found {
    std::vector<PairContact> contacts;
    std::vector<HandoverMismatch> handovers;
    std::vector<std::size_t> contacts_end;
    std::vector<std::size_t> handovers_end;
    PairMinima minima;
    std::size_t evaluations = 0;
  };
  std::vector<Found> found(threads);
  std::atomic<bool> stopped{false};
  auto work = [&](std::size_t w) {
    StretchChecker checker(world, motion, timeline, supports, options);
    Found& mine = found[w];
    // Interleaved, so that every thread gets its share of the busy parts of the plan.
    for (std::size_t i = w; i < stretches.size(); i += threads) {
      if (stopped.load(std::memory_order_relaxed) || (options.stop && options.stop())) {
        stopped.store(true, std::memory_order_relaxed);
        return;
      }
      checkHandovers(world, motion, timeline, options, stretches[i], mine.handovers);
      if (options.check_geometry) checker.check(stretches[i], mine.contacts, mine.minima);
      mine.contacts_end.push_back(mine.contacts.size());
      mine.handovers_end.push_back(mine.handovers.size());
    }
    mine.evaluations = checker.evaluations();
  };
  runWorkers(threads, work);
  if (stopped.load()) {
    report.stopped = true;  // the findings cover part of the plan: none is reported
    return;
  }
  // The report must not depend on the number of threads (a planner feeds its first problem back): the
  // findings go on in stretch order, exactly as one thread makes them; the minima and the count of
  // distance evaluations do not depend on the order (mergeMinima keeps a total order; every stretch
  // counts its own evaluations).
  std::vector<PairContact> contacts;
  std::vector<HandoverMismatch> handovers;
  for (std::size_t i = 0; i < stretches.size(); ++i) {
    const Found& part = found[i % threads];
    const std::size_t k = i / threads;
    const std::size_t c0 = k == 0 ? 0 : part.contacts_end[k - 1];
    const std::size_t h0 = k == 0 ? 0 : part.handovers_end[k - 1];
    contacts.insert(contacts.end(), part.contacts.begin() + static_cast<std::ptrdiff_t>(c0),
                    part.contacts.begin() + static_cast<std::ptrdiff_t>(part.contacts_end[k]));
    handovers.insert(handovers.end(), part.handovers.begin() + static_cast<std::ptrdiff_t>(h0),
                     part.handovers.begin() + static_cast<std::ptrdiff_t>(part.handovers_end[k]));
  }
  PairMinima minima;
  for (const Found& part : found) {
    mergeMinima(minima, part.minima);
    report.samples += part.evaluations;
  }
  if (options.check_geometry) {
    for (const ValidationProblem& p : restingObjectProblems(world, timeline)) report.problems.push_back(p);
  }
  appendContactProblems(scene, options, std::move(contacts), kJoinTolerance, report.problems);
  appendHandoverProblems(scene, options, std::move(handovers), report.problems);
  fillClearances(scene, minima, report);
}

}  // namespace dash::validation
