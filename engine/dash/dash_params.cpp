#include "engine/dash/dash_params.h"

namespace dash {

void applyDashParameters(DashParams& p, const ParamValues& v) {
  auto set = [&](const char* name, bool& field) {
    if (v.contains(name)) field = paramBool(v, name);
  };
  auto size = [&](const char* name, std::size_t& field) {
    if (v.contains(name)) field = static_cast<std::size_t>(paramInt(v, name));
  };
  set("greedy_move_pruning", p.query.prune_moves);
  set("one_object_pass", p.query.one_object_pass);
  set("complete_pass", p.query.complete_pass);
  set("stranding_prune", p.query.stranding_prune);
  // Off: every grasp chain searches the whole pose grid, as the first search of a hyperarc does.
  if (v.contains("targeted_handovers") && !paramBool(v, "targeted_handovers"))
    p.transitions.targeted_handover_poses = p.transitions.handover_poses;
  set("approach_line_preference", p.transitions.approach_line);
  if (v.contains("deep_backoffs") && !paramBool(v, "deep_backoffs")) p.transitions.deep_approach_distances.clear();
  set("shortcutting", p.shortcutting);
  if (v.contains("validator_rechecks")) p.validator_rechecks = paramInt(v, "validator_rechecks");
  size("empty_roadmap_samples", p.empty_roadmap_samples);
  size("holding_roadmap_samples", p.holding_roadmap_samples);
  size("growth_samples", p.growth_samples);
  if (v.contains("grow_roadmap_probability"))
    p.break_rule.grow_roadmap_probability = paramReal(v, "grow_roadmap_probability");
  if (v.contains("clearance")) p.clearance = paramReal(v, "clearance");
  if (v.contains("validation_threads")) p.validation_threads = paramInt(v, "validation_threads");
  applySchedulerParameters(p.scheduler, v);
}

}  // namespace dash
