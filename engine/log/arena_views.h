#pragma once
// Planner Arena compatibility (https://plannerarena.org, OMPL's benchmark database format) as
// views over the dash_* tables, so that one results file loads in Planner Arena unchanged.
//
// Design:
// - `experiments` is a view with Planner Arena's 12 columns first and in order (id, name, totaltime,
//   timelimit, memorylimit, runcount, version, hostname, cpuinfo, date, seed, setup), then one
//   column per scenario parameter: the union of every parameter name of every experiment in the
//   file, NULL where a family does not have that parameter. The view is rebuilt (DROP/CREATE) only
//   when that set of names changes: beginRun of a new experiment, a merge, or a migration.
// - An experiment is (scenario family, parameter values, code version). The version is part of the
//   key because Planner Arena keeps the version on the experiment row; its version selector and
//   regression plots need one experiment per version. `name` is the family, so Planner Arena lists
//   one "problem" per family and offers the parameters as filters.
// - A parameter whose name clashes with a column Planner Arena joins on (the 12 above, `experiment`,
//   `planner`, or a `runs` attribute) is exposed as `param_<name>`.
// - `plannerConfigs` is one row per (configuration name, planner, settings JSON).
// - `runs` lists finished runs only (status is not 'running'): id, experimentid, plannerid, then
//   the attributes; `status` is an integer from `enums` (values follow OMPL's PlannerStatus:
//   4 timeout, 6 solved (exact solution), 7 crashed, 8 cancelled (abort), 9 infeasible).
// - `progress` is (runid, time, then representation sizes, roadmap sizes, active constraints,
//   collision checks) from the recorder's snapshots.
// - `enums` is a real table (schema version 1), since its rows are fixed.
// - `dash_events` shows dash_repr_events (schema version 4) with layer, kind and change by name.
// - `dash_timeline` is every event of every run in one ordered list (run_id, seq), for drill-down.
#include <string>
#include <vector>

struct sqlite3;

namespace dash::log {

/// The attribute columns of the `runs` view, after id, experimentid, plannerid.
const std::vector<std::string>& arenaRunAttributes();

/// Recreates every derived view whose definition changed (cheap when nothing did). Needs a
/// writable connection; runs inside the caller's transaction if there is one.
void refreshArenaViews(sqlite3* db);

/// The column name under which a scenario parameter appears in `experiments`.
std::string arenaParameterColumn(const std::string& parameter);

}  // namespace dash::log
