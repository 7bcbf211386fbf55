#include "engine/planners/lazy_dash.h"

#include <type_traits>

#include "engine/core/planner_params.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/planners/lazy_dash_run.h"

namespace dash {

void applyParameters(LazyDashParams& p, const ParamValues& v) {
  auto set = [&](const char* name, auto& field) {
    if (!v.contains(name)) return;
    using T = std::decay_t<decltype(field)>;
    if constexpr (std::is_same_v<T, bool>) field = paramBool(v, name);
    else field = static_cast<T>(paramInt(v, name));
  };
  set("straight_first", p.motion.straight_first);
  set("global_sampling", p.motion.global_sampling);
  set("path_simplification", p.motion.roadmap.simplify);
  set("keep_tree_paths", p.motion.roadmap.keep_tree_paths);
  set("roadmap_query_samples", p.motion.roadmap.query_samples);
  set("roadmap_max_vertices", p.motion.roadmap.max_vertices);
  if (v.contains("deep_backoffs") && !paramBool(v, "deep_backoffs")) p.motion.deep_approach_distances.clear();
  set("round_trip_removal", p.task.query.remove_round_trips);
  set("approach_line_preference", p.task.conflicts.prefer_free_approach);
  set("handover_class_bans", p.task.handover_class_bans);
  set("transition_resamples", p.max_transition_resamples);
  set("move_out_resamples", p.task.conflicts.chain_location_resamples);
  set("move_out_one_grasp", p.task.move_out_one_grasp);
  set("budget_growth", p.budget_growth);
  set("validator_rechecks", p.validator_rechecks);
  set("validation_feedbacks", p.validation_feedbacks);
  set("validation_threads", p.validation_threads);
  set("motion_budget", p.motion_budget);
  set("restart_when_exhausted", p.restart_when_exhausted);
  set("max_task_plans", p.max_task_plans);
  set("move_outs_per_object", p.task.max_extra_locations_per_object);
  set("ban_queries", p.task.max_ban_queries);
  set("ban_lifts", p.task.max_ban_lifts);
  if (v.contains("handover_base_distance"))
    p.task.reachability.max_handover_base_distance = paramReal(v, "handover_base_distance");
  if (v.contains("clearance")) p.clearance = paramReal(v, "clearance");
  applySchedulerParameters(p.scheduler, v);
}

PlanResult LazyDash::solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                           log::EventSink* sink) {
  applyTestFault(settings);
  // Named parameters: checked (InputError naming a bad one), then applied over the constructor's.
  const ParamValues effective = resolveParameters(name(), settings.params);
  LazyDashParams params = params_;
  ParamValues overrides;
  for (const auto& [key, value] : settings.params) overrides[key] = effective.at(key);
  applyParameters(params, overrides);
  const OmplSeedScope ompl_seeds(settings.seed);
  log::EventEmitter emitter(sink);
  // Every second of the solve is in one phase: what no layer books (setup, the loop's own bookkeeping)
  // is "other", so the phases add up to the wall time (docs/planners.md "Phases").
  log::PhaseTimer other(emitter, log::Phase::Other);
  LazyDashRun run(scene, params, settings, deadline, emitter, name());
  PlanResult result = run.run();
  other.stop();
  result.stats.phase_seconds = emitter.phaseTotals();
  result.stats.wall_seconds = emitter.now();
  return result;
}

}  // namespace dash
