#include "engine/dash/dash_planner.h"

#include "engine/dash/dash_run.h"

namespace dash {

PlanResult DashPlanner::solve(const Scene& scene, const PlannerSettings& settings, const Deadline& deadline,
                              log::EventSink* sink) {
  applyTestFault(settings);
  // The named parameters given (engine/core/planner_params.h), checked and applied over params_.
  DashParams params = params_;
  const ParamValues effective = resolveParameters(name(), settings.params);
  ParamValues overrides;
  for (const auto& entry : settings.params) overrides[entry.first] = effective.at(entry.first);
  applyDashParameters(params, overrides);
  DashRun run(params, name(), scene, settings, deadline, sink);
  return run.solve();
}

}  // namespace dash
