#include "engine/planners/planner.h"

#include "engine/core/check.h"
#include "engine/dash/dash_planner.h"
#include "engine/planners/lazy_dash.h"

namespace dash {

const char* toString(PlanOutcome outcome) {
  switch (outcome) {
    case PlanOutcome::kSolved: return "solved";
    case PlanOutcome::kTimeout: return "timeout";
    case PlanOutcome::kInfeasible: return "infeasible";
    case PlanOutcome::kCancelled: return "cancelled";
  }
  return "?";
}

std::vector<std::string> plannerNames() { return {"lazy-dash", "dash"}; }

std::unique_ptr<Planner> makePlanner(const std::string& name) {
  if (name == "lazy-dash") return std::make_unique<LazyDash>();
  if (name == "dash") return std::make_unique<DashPlanner>();
  std::string known;
  for (const auto& n : plannerNames()) known += (known.empty() ? "" : ", ") + n;
  throw InputError("unknown planner '" + name + "' (known: " + known + ")");
}

std::unique_ptr<Planner> makePlanner(const std::string& name, double clearance) {
  if (name == "lazy-dash") {
    LazyDashParams params;
    params.clearance = clearance;
    return std::make_unique<LazyDash>(params);
  }
  if (name == "dash") {
    DashParams params;
    params.clearance = clearance;
    return std::make_unique<DashPlanner>(params);
  }
  return makePlanner(name);
}

}  // namespace dash
