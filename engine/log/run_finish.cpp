// How a run's outcome is written: the summary, with unset figures derived from its stored events.
#include <sqlite3.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

#include "engine/core/check.h"
#include "engine/log/results_db_impl.h"
#include "engine/log/run_columns.h"

namespace dash::log {
namespace {

template <std::size_t N>
int nameIndex(const std::array<const char*, N>& names, const std::string& name) {
  for (std::size_t i = 0; i < N; ++i) {
    if (name == names[i]) return static_cast<int>(i);
  }
  return -1;
}

void see(RunFigures& f, const sql::Statement& st, int count_col, int iteration_col, int t_col) {
  f.events += st.columnInt(count_col);
  f.max_iteration = std::max(f.max_iteration, st.columnInt(iteration_col));
  f.last_t = std::max(f.last_t, st.columnDouble(t_col));
}

// What a run's stored events say, for the figures a summary leaves unset (when the writer has no
// tally of them: a run recorded by another process, or one whose recording failed).
RunFigures deriveFromTables(sqlite3* db, std::int64_t run_id) {
  RunFigures d;
  sql::Statement ev(db,
                    "SELECT layer, kind, SUM(CASE change WHEN 0 THEN 1 ELSE -1 END), COUNT(*), MAX(iteration), "
                    "MAX(t) FROM dash_repr_events WHERE run_id = ? GROUP BY layer, kind");
  ev.bind(1, run_id);
  while (ev.step()) {
    const std::int64_t layer = ev.columnInt(0);
    if (layer >= 0 && layer < kLayerCount) {
      (ev.columnInt(1) == static_cast<int>(ElementKind::Vertex) ? d.sizes.vertices : d.sizes.hyperarcs)[layer] =
          ev.columnInt(2);
    }
    see(d, ev, 3, 4, 5);
  }
  sql::Statement ph(db, "SELECT phase, SUM(duration), COUNT(*), MAX(iteration), MAX(t_end) FROM dash_phases "
                        "WHERE run_id = ? GROUP BY phase");
  ph.bind(1, run_id);
  while (ph.step()) {
    if (const int p = nameIndex(kPhaseNames, ph.columnText(0)); p >= 0) d.phases[p] = ph.columnDouble(1);
    see(d, ph, 2, 3, 4);
  }
  sql::Statement co(db, "SELECT kind, SUM(action = 'created'), SUM(CASE action WHEN 'created' THEN 1 ELSE -1 END), "
                        "COUNT(*), MAX(iteration), MAX(t) FROM dash_constraints WHERE run_id = ? GROUP BY kind");
  co.bind(1, run_id);
  while (co.step()) {
    if (const int k = nameIndex(kConstraintKindNames, co.columnText(0)); k >= 0) d.constraints[k] = co.columnInt(1);
    d.active_constraints += co.columnInt(2);
    see(d, co, 3, 4, 5);
  }
  sql::Statement ex(db, "SELECT COUNT(*), MAX(iteration), MAX(t) FROM dash_expansions WHERE run_id = ?");
  ex.bind(1, run_id);
  if (ex.step()) {
    d.expansions = ex.columnInt(0);
    see(d, ex, 0, 1, 2);
  }
  // SQLite takes the bare column `value` from the row holding MAX(seq): the latest value.
  sql::Statement cn(db, "SELECT name, value, MAX(seq) FROM dash_counters WHERE run_id = ? GROUP BY name");
  cn.bind(1, run_id);
  while (cn.step()) d.counters[cn.columnText(0)] = cn.columnInt(1);
  sql::Statement cs(db, "SELECT COUNT(*), MAX(iteration), MAX(t) FROM dash_counters WHERE run_id = ?");
  cs.bind(1, run_id);
  if (cs.step()) see(d, cs, 0, 1, 2);
  return d;
}

std::optional<std::int64_t> counterOf(const RunFigures& d, const char* name) {
  auto it = d.counters.find(name);
  if (it == d.counters.end()) return std::nullopt;
  return it->second;
}

}  // namespace

void finishRunLocked(ResultsDb::Impl& m, std::int64_t run_id, const RunSummary& s, std::optional<double> elapsed,
                     const std::string& recorder_error, const RunFigures* figures) {
  const RunFigures d = figures != nullptr ? *figures : deriveFromTables(m.db.get(), run_id);
  const PhaseTotals phases = s.phase_seconds.value_or(d.phases);
  const RepresentationSizes sizes = s.sizes.value_or(d.sizes);
  const auto constraints = s.constraints.value_or(d.constraints);
  const double total = s.total_time ? *s.total_time : elapsed ? *elapsed : d.last_t;
  const auto eager = s.collision_checks_eager ? s.collision_checks_eager : counterOf(d, "collision_checks_eager");
  const auto lazy = s.collision_checks_lazy ? s.collision_checks_lazy : counterOf(d, "collision_checks_lazy");
  std::optional<std::int64_t> checks = counterOf(d, "collision_checks");
  if (eager || lazy) checks = eager.value_or(0) + lazy.value_or(0);
  const auto roadmap_vertices = s.roadmap_vertices ? s.roadmap_vertices : counterOf(d, "roadmap_vertices");
  const auto roadmap_edges = s.roadmap_edges ? s.roadmap_edges : counterOf(d, "roadmap_edges");

  std::string error = s.error;
  if (!recorder_error.empty()) {
    if (!error.empty()) error += "; ";
    error += "recording stopped: " + recorder_error;
  }

  m.beginWriteLocked();
  sql::Statement up(m.db.get(), std::string("UPDATE dash_runs SET ") + kFinishAssignments + " WHERE id = ?");
  auto b = up.binder();
  b(isoNow())(toString(s.status)).orNull(error)(s.exit_signal)(total);
  for (double p : phases) b(p);
  b(s.iterations.value_or(d.max_iteration));
  for (int l = 0; l < kLayerCount; ++l) b(sizes.vertices[l])(sizes.hyperarcs[l]);
  b(roadmap_vertices)(roadmap_edges);
  for (std::int64_t c : constraints) b(c);
  b(s.task_space_expansions.value_or(d.expansions))(checks)(eager)(lazy);
  b(s.makespan)(s.path_length)(s.peak_memory_mb).orNull(s.plan_json)(d.events)(s.wall_time)(s.phase_accounting)(run_id);
  up.run();

  sql::Statement& pr = m.insert_progress;
  pr.bind(1, run_id).bind(2, total).bind(3, s.iterations.value_or(d.max_iteration));
  for (int l = 0; l < kLayerCount; ++l) pr.bind(4 + 2 * l, sizes.vertices[l]).bind(5 + 2 * l, sizes.hyperarcs[l]);
  pr.bind(12, roadmap_vertices.value_or(0)).bind(13, roadmap_edges.value_or(0)).bind(14, d.active_constraints);
  pr.bind(15, checks.value_or(0));
  // A long phase's progress as the run's last snapshot before this one left it (NULL: none).
  for (int i = 16; i <= 20; ++i) pr.bindNull(i);
  sql::Statement last(m.db.get(), "SELECT progress_phase, progress_done, progress_total, progress_rate, progress_current "
                                  "FROM dash_progress WHERE run_id = ? AND progress_phase IS NOT NULL ORDER BY t DESC LIMIT 1");
  last.bind(1, run_id);
  if (last.step()) {
    pr.bind(16, last.columnText(0)).bind(17, last.columnInt(1)).bind(18, last.columnInt(2));
    pr.bind(19, last.columnDouble(3));
    if (!std::holds_alternative<std::monostate>(last.columnValue(4))) pr.bind(20, last.columnText(4));
  }
  pr.run();
  m.commitLocked();
}

std::string isoNow() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  char text[64];
  std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1,
                tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(ms));
  return text;
}

std::int64_t runIdOf(sqlite3* db, const std::string& uuid) {
  sql::Statement st(db, "SELECT id FROM dash_runs WHERE uuid = ?");
  st.bind(1, uuid);
  DASH_THROW_UNLESS(st.step(), "no run with uuid " + uuid);
  return st.columnInt(0);
}

}  // namespace dash::log
