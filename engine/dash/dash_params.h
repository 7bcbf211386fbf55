#pragma once
// DaSH's parameters (dash_planner.h) and the named planner parameters that set them
// (engine/core/planner_params.h: `dashbench plan --params --planner dash`, `--set`, `--profile paper`).
// Every addition beyond the DaSH paper (Motes et al., T-RO 2023) is a switch here, on by default and
// off in the paper profile: the one-object and complete query passes, the greedy pass's pruned moves,
// the stranding prune, targeted handover pose subsets, the approach-line and deep back-off
// candidates, path shortcutting and validator re-checks. docs/planners.md has the table.
#include <cstddef>

#include "engine/collision/collision_world.h"
#include "engine/conflict/scheduler.h"
#include "engine/core/planner_params.h"
#include "engine/dash/break_rule.h"
#include "engine/dash/combined_query.h"
#include "engine/dash/placement_sampling.h"
#include "engine/dash/transition_catalog.h"
#include "engine/dash/validated_roadmap.h"

namespace dash {

struct DashParams {
  PlacementSamplingParams placements;
  TransitionCatalogParams transitions;
  ValidatedRoadmapParams roadmap;
  std::size_t empty_roadmap_samples = 100;    ///< og::PRM milestones per robot, empty hand
  std::size_t holding_roadmap_samples = 60;   ///< og::PRM milestones per robot, holding
  std::size_t growth_samples = 50;            ///< milestones added per roadmap growth
  BreakRuleParams break_rule;                 ///< CBS-MP: grow roadmaps or the constraint tree
  CombinedQueryParams query;
  SchedulerParams scheduler;
  /// Beyond DaSH: the hyperpath's roadmap paths are shortened (straight segments) before scheduling.
  bool shortcutting = true;
  /// Beyond DaSH: a contact the validator finds is checked at from then on and the same hyperpath
  /// scheduled again, this many times per constraint tree node (then it is a conflict).
  int validator_rechecks = 3;
  /// Metres every check of the planner keeps between parts not in contact by design (collision_world.h).
  double clearance = kDefaultPlanningClearance;
  /// Threads of the validator run on each schedule (0: the hardware's); its report, hence the plan,
  /// is the same for any number.
  int validation_threads = 0;
};

/// Applies the named parameters present in `values` (checked by resolveParameters) to `params`;
/// names absent leave its fields as they are.
void applyDashParameters(DashParams& params, const ParamValues& values);

}  // namespace dash
