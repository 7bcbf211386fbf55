#include "engine/log/run_columns.h"

namespace dash::log {

const char* const kFinishAssignments =
    "end_time = ?, status = ?, error = ?, exit_signal = ?, total_time = ?, time_task_construction = ?, "
    "time_task_query = ?, time_task_conflict_detection = ?, time_motion_construction = ?, time_motion_query = ?, "
    "time_conflict_resolution = ?, time_validation = ?, time_other = ?, iterations = ?, task_vertices = ?, task_hyperarcs = ?, "
    "task_extended_vertices = ?, task_extended_hyperarcs = ?, motion_vertices = ?, motion_hyperarcs = ?, "
    "motion_extended_vertices = ?, motion_extended_hyperarcs = ?, roadmap_vertices = ?, roadmap_edges = ?, "
    "constraints_frontier = ?, constraints_history = ?, constraints_motion = ?, constraints_interaction = ?, "
    "task_space_expansions = ?, collision_checks = ?, collision_checks_eager = ?, collision_checks_lazy = ?, "
    "makespan = ?, path_length = ?, peak_memory = ?, plan = ?, event_count = ?, wall_time = ?, phase_accounting = ?";

const char* const kRunSelectColumns =
    "r.id, r.uuid, r.batch_id, r.family, r.scene, r.params, r.seed, r.planner, r.planner_settings, "
    "(SELECT name FROM dash_planner_configs WHERE id = r.planner_config_id), r.time_limit, r.memory_limit, "
    "r.code_version, r.host, r.cpu_info, r.start_time, r.end_time, r.status, r.error, r.exit_signal, r.total_time, "
    "r.time_task_construction, r.time_task_query, r.time_task_conflict_detection, r.time_motion_construction, "
    "r.time_motion_query, r.time_conflict_resolution, r.time_validation, r.time_other, r.iterations, r.task_vertices, r.task_hyperarcs, "
    "r.task_extended_vertices, r.task_extended_hyperarcs, r.motion_vertices, r.motion_hyperarcs, "
    "r.motion_extended_vertices, r.motion_extended_hyperarcs, r.roadmap_vertices, r.roadmap_edges, "
    "r.constraints_frontier, r.constraints_history, r.constraints_motion, r.constraints_interaction, "
    "r.task_space_expansions, r.collision_checks, r.collision_checks_eager, r.collision_checks_lazy, r.makespan, "
    "r.path_length, r.peak_memory, r.event_count, r.note, r.wall_time, r.phase_accounting, "
    "(SELECT group_concat(tag, char(31)) FROM dash_run_tags WHERE run_id = r.id)";
const int kRunSelectColumnCount = 56;

RunRecord readRunRecord(const sql::Statement& st) {
  RunRecord r;
  int i = 0;
  auto text = [&] { return st.columnText(i++); };
  auto optInt = [&] { return st.columnOptInt(i++); };
  auto optReal = [&] { return st.columnOptDouble(i++); };
  r.id = st.columnInt(i++);
  RunMetadata& m = r.meta;
  m.uuid = text();
  m.batch_id = text();
  m.family = text();
  m.scene = text();
  m.params_json = text();
  m.seed = static_cast<std::uint64_t>(st.columnInt(i++));
  m.planner = text();
  m.planner_settings_json = text();
  m.planner_config_name = text();
  m.time_limit = optReal();
  m.memory_limit = optReal();
  m.code_version = text();
  m.host = text();
  m.cpu_info = text();
  r.start_time = text();
  r.end_time = text();
  r.status = parseRunStatus(text());
  RunSummary& s = r.summary;
  s.status = r.status;
  s.error = text();
  if (auto sig = optInt()) s.exit_signal = static_cast<int>(*sig);
  s.total_time = optReal();
  if (!st.isNull(i)) {
    PhaseTotals phases{};
    for (double& p : phases) p = st.columnDouble(i++);
    s.phase_seconds = phases;
  } else {
    i += kPhaseCount;
  }
  s.iterations = optInt();
  if (!st.isNull(i)) {
    RepresentationSizes sizes;
    for (int l = 0; l < kLayerCount; ++l) {
      sizes.vertices[l] = st.columnInt(i++);
      sizes.hyperarcs[l] = st.columnInt(i++);
    }
    s.sizes = sizes;
  } else {
    i += 2 * kLayerCount;
  }
  s.roadmap_vertices = optInt();
  s.roadmap_edges = optInt();
  if (!st.isNull(i)) {
    std::array<std::int64_t, kConstraintKindCount> constraints{};
    for (auto& c : constraints) c = st.columnInt(i++);
    s.constraints = constraints;
  } else {
    i += kConstraintKindCount;
  }
  s.task_space_expansions = optInt();
  r.collision_checks = optInt();
  s.collision_checks_eager = optInt();
  s.collision_checks_lazy = optInt();
  s.makespan = optReal();
  s.path_length = optReal();
  s.peak_memory_mb = optReal();
  r.event_count = optInt().value_or(0);
  r.note = text();
  s.wall_time = optReal();
  if (auto accounting = optInt()) s.phase_accounting = static_cast<int>(*accounting);
  return r;
}

}  // namespace dash::log
