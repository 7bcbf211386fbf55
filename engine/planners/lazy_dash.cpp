#include "engine/planners/lazy_dash.h"

#include <cstdlib>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_world.h"
#include "engine/task/task_layer.h"

namespace dash {

namespace {

void applyTestFault(const PlannerSettings& settings, const Deadline& deadline) {
  if (settings.test_fault == "abort") std::abort();
  if (settings.test_fault == "ignore-deadline") {
    volatile std::uint64_t spin = 0;
    for (;;) spin = spin + 1;  // never returns: the batch runner must kill it from outside
  }
  (void)deadline;
}

PlanOutcome outcomeOf(TaskLayerStatus status, const Deadline& deadline) {
  if (status == TaskLayerStatus::kFeasible) return PlanOutcome::kSolved;
  if (status == TaskLayerStatus::kTimeout) return deadline.stopRequested() ? PlanOutcome::kCancelled : PlanOutcome::kTimeout;
  return PlanOutcome::kInfeasible;
}

void fillTaskStats(const TaskLayer& task, PlanStats& stats) {
  const TaskLayerSizes s = task.sizes();
  stats.sizes.task_vertices = s.task_vertices;
  stats.sizes.task_hyperarcs = s.task_hyperarcs;
  stats.sizes.task_extended_vertices = s.task_extended_vertices;
  stats.sizes.task_extended_hyperarcs = s.task_extended_hyperarcs;
  stats.task_constraints = static_cast<std::int64_t>(task.constraints().size());
  int expansions = 0;
  for (int o = 0; o < task.space().objectCount(); ++o) expansions += task.space().extraLocationCount(o);
  stats.task_space_expansions = expansions;
  stats.iterations = task.queries();
}

}  // namespace

PlanResult LazyDash::solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                           log::EventSink* sink) {
  applyTestFault(settings, deadline);
  log::EventEmitter emitter(sink);
  const CollisionWorld world(scene);
  CollisionContext context(world);
  TaskLayer task(scene, world, context, emitter, settings.seed);
  PlanResult result;
  const TaskLayerResult layer = task.plan(deadline);
  fillTaskStats(task, result.stats);
  result.stats.collision_checks_lazy = static_cast<std::int64_t>(context.counters().configuration_checks);
  result.stats.phase_seconds = emitter.phaseTotals();
  if (layer.status != TaskLayerStatus::kFeasible) {
    result.outcome = outcomeOf(layer.status, deadline);
    result.message = "task layer: " + std::string(toString(layer.status)) +
                     (layer.reason.empty() ? "" : " (" + layer.reason + ")");
    return result;
  }
  result.message = layer.plan.describe(task.space());
  result.task_plan_json = layer.plan.toJson(task.space());
  if (settings.task_only) {
    result.outcome = PlanOutcome::kSolved;
    return result;
  }
  result.outcome = PlanOutcome::kInfeasible;
  result.message = "the motion layer is not part of this build yet: only --task-only runs can succeed";
  return result;
}

}  // namespace dash
