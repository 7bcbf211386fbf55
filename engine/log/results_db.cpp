#include "engine/log/results_db.h"

#include <sqlite3.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <thread>

#include "engine/core/check.h"
#include "engine/log/arena_views.h"
#include "engine/log/results_db_impl.h"
#include "engine/log/results_schema.h"
#include "engine/log/run_columns.h"
#include "engine/log/sqlite_recorder.h"

// DASHBENCH_CODE_VERSION: git describe of the source tree at build time (code_version.cmake).
#include "dash_code_version.h"
#include "engine/core/host_info.h"

namespace dash::log {
namespace {

constexpr std::array<const char*, 6> kStatusNames = {"running", "solved", "timeout", "infeasible", "crashed",
                                                     "cancelled"};


std::string cpuInfo() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) == 0) {
      if (auto colon = line.find(':'); colon != std::string::npos) model = line.substr(colon + 2);
      break;
    }
  }
  return model + " (" + std::to_string(std::thread::hardware_concurrency()) + " threads)";
}

bool validParameterName(const std::string& name) {
  if (name.empty()) return false;
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  }
  return true;
}

// Parses a JSON object and prints it canonically (keys sorted, no spaces), so that equal
// parameter sets and settings compare equal as text.
std::string canonicalObject(const std::string& text, const std::string& what, bool check_names) {
  nlohmann::json value;
  try {
    value = nlohmann::json::parse(text.empty() ? "{}" : text);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(what + " is not valid JSON: " + e.what());
  }
  DASH_THROW_UNLESS(value.is_object(), what + " must be a JSON object");
  if (check_names) {
    for (const auto& [key, v] : value.items()) {
      DASH_THROW_UNLESS(validParameterName(key), what + ": parameter name '" + key +
                                                     "' may only hold letters, digits, '_', '-' and '.'");
    }
  }
  return value.dump();
}

std::vector<std::string> objectKeys(const std::string& canonical) {
  std::vector<std::string> keys;
  const nlohmann::json object = nlohmann::json::parse(canonical);  // must outlive items()
  for (const auto& [key, v] : object.items()) keys.push_back(key);
  return keys;
}

}  // namespace

const char* toString(RunStatus status) { return kStatusNames[static_cast<int>(status)]; }

RunStatus parseRunStatus(const std::string& name) {
  const auto it = std::find(kStatusNames.begin(), kStatusNames.end(), name);
  const int i = it == kStatusNames.end() ? -1 : static_cast<int>(it - kStatusNames.begin());
  DASH_THROW_UNLESS(i >= 0, "unknown run status '" + name +
                                "' (running, solved, timeout, infeasible, crashed or cancelled)");
  return static_cast<RunStatus>(i);
}

double processPeakMemoryMb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
}

// ---- Impl ----

void ResultsDb::Impl::requireWritable() const {
  DASH_THROW_UNLESS(mode == OpenMode::ReadWrite, path + " is open read-only");
}

void ResultsDb::Impl::beginWriteLocked() {
  if (in_transaction) return;
  sql::exec(db.get(), "BEGIN IMMEDIATE");
  in_transaction = true;
}

void ResultsDb::Impl::commitLocked() {
  if (!in_transaction) return;
  in_transaction = false;
  try {
    sql::exec(db.get(), "COMMIT");
  } catch (...) {
    rollbackLocked();
    throw;
  }
}

void ResultsDb::Impl::rollbackLocked() noexcept {
  in_transaction = false;
  if (!sqlite3_get_autocommit(db.get())) sqlite3_exec(db.get(), "ROLLBACK", nullptr, nullptr, nullptr);
}

// ---- ResultsDb ----

ResultsDb::ResultsDb(const std::string& path, OpenMode mode, DbOptions options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.mode = mode;
  m.options = options;
  const int flags = mode == OpenMode::ReadOnly ? SQLITE_OPEN_READONLY
                                               : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE | SQLITE_OPEN_URI;
  m.db = sql::open(path, flags | SQLITE_OPEN_NOMUTEX);
  sqlite3_busy_timeout(m.db.get(), options.busy_timeout_ms);
  if (mode == OpenMode::ReadOnly) {
    checkSchemaReadable(m.db.get(), path);
    sql::exec(m.db.get(), "PRAGMA query_only = 1");
    return;
  }
  sql::exec(m.db.get(), "PRAGMA journal_mode = WAL");
  // In WAL mode, NORMAL loses no committed transaction to a process crash (only to power loss).
  sql::exec(m.db.get(), "PRAGMA synchronous = NORMAL");
  migrateSchema(m.db.get(), path);
  sql::Statement names(m.db.get(), "SELECT DISTINCT j.key FROM dash_experiments e, json_each(e.params) j");
  while (names.step()) m.parameter_names.insert(names.columnText(0));
  refreshArenaViews();
  sqlite3* db = m.db.get();
  const std::string insert_events = "INSERT INTO dash_repr_events (run_id, seq, t, iteration, layer, kind, change, "
                                    "arc_type, element_id, head, tail, label) VALUES ";
  const std::string one_event = "(?,?,?,?,?,?,?,?,?,?,?,?)";
  std::string many_events = insert_events + one_event;
  for (int r = 1; r < Impl::kRowsPerInsert; ++r) many_events += "," + one_event;
  m.insert_event = sql::Statement(db, insert_events + one_event);
  m.insert_events = sql::Statement(db, many_events);
  m.insert_constraint = sql::Statement(db, "INSERT INTO dash_constraints (run_id, seq, t, iteration, kind, action, "
                                           "constraint_id, content, vertices, conflict) VALUES (?,?,?,?,?,?,?,?,?,?)");
  m.insert_expansion = sql::Statement(db, "INSERT INTO dash_expansions (run_id, seq, t, iteration, object_id, "
                                          "object_label, added, reason) VALUES (?,?,?,?,?,?,?,?)");
  m.insert_phase = sql::Statement(db, "INSERT INTO dash_phases (run_id, seq, iteration, phase, t_start, t_end, "
                                      "duration) VALUES (?,?,?,?,?,?,?)");
  m.insert_counter = sql::Statement(db, "INSERT INTO dash_counters (run_id, seq, t, iteration, name, value) "
                                        "VALUES (?,?,?,?,?,?)");
  m.insert_progress = sql::Statement(
      db, "INSERT OR REPLACE INTO dash_progress (run_id, t, iteration, task_vertices, task_hyperarcs, "
          "task_extended_vertices, task_extended_hyperarcs, motion_vertices, motion_hyperarcs, motion_extended_vertices, "
          "motion_extended_hyperarcs, roadmap_vertices, roadmap_edges, constraints, collision_checks, progress_phase, "
          "progress_done, progress_total, progress_rate, progress_current) "
          "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
}

ResultsDb::~ResultsDb() {
  Impl& m = *impl_;
  std::vector<SqliteRecorder*> recorders;
  {
    std::lock_guard lock(m.mutex);
    for (auto& [uuid, run] : m.active) {
      if (run.recorder != nullptr) recorders.push_back(run.recorder);
    }
  }
  for (SqliteRecorder* r : recorders) r->handOver(true);
  m.stopWriter();  // writes everything queued
  for (SqliteRecorder* r : recorders) {
    std::lock_guard lock(r->mutex_);
    r->db_ = nullptr;
  }
}

const std::string& ResultsDb::path() const { return impl_->path; }

int ResultsDb::schemaVersion() const {
  std::lock_guard lock(impl_->mutex);
  return readSchemaVersion(impl_->db.get());
}

std::string ResultsDb::beginRun(const RunMetadata& meta) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(!meta.family.empty(), "a run needs a scenario family");
  DASH_THROW_UNLESS(!meta.planner.empty(), "a run needs a planner");
  const std::string params = canonicalObject(meta.params_json, "scenario parameters", true);
  const std::string settings = canonicalObject(meta.planner_settings_json, "planner settings", false);
  const std::string uuid = meta.uuid.empty() ? newUuid() : meta.uuid;
  const std::string version = meta.code_version.empty() ? DASHBENCH_CODE_VERSION : meta.code_version;
  std::string config_name = meta.planner_config_name;
  if (config_name.empty()) config_name = settings == "{}" ? meta.planner : meta.planner + " " + settings;

  std::lock_guard lock(m.mutex);
  sqlite3* db = m.db.get();
  {
    sql::Statement exists(db, "SELECT 1 FROM dash_runs WHERE uuid = ?");
    exists.bind(1, uuid);
    DASH_THROW_UNLESS(!exists.step(), "a run with uuid " + uuid + " already exists in " + m.path);
  }
  m.beginWriteLocked();
  try {
    sql::Statement add_experiment(db, "INSERT OR IGNORE INTO dash_experiments (family, params, version) VALUES (?,?,?)");
    add_experiment.bind(1, meta.family).bind(2, params).bind(3, version).run();
    bool new_names = false;
    for (const std::string& key : objectKeys(params)) new_names |= m.parameter_names.insert(key).second;
    if (new_names) dash::log::refreshArenaViews(db);
    sql::Statement add_config(db, "INSERT OR IGNORE INTO dash_planner_configs (name, planner, settings) VALUES (?,?,?)");
    add_config.bind(1, config_name).bind(2, meta.planner).bind(3, settings).run();

    sql::Statement add_run(
        db,
        "INSERT INTO dash_runs (uuid, batch_id, experiment_id, planner_config_id, family, scene, params, seed, planner, "
        "planner_settings, time_limit, memory_limit, code_version, host, cpu_info, start_time, status) VALUES (?, ?, "
        "(SELECT id FROM dash_experiments WHERE family = ? AND params = ? AND version = ?), "
        "(SELECT id FROM dash_planner_configs WHERE name = ? AND planner = ? AND settings = ?), "
        "?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?, 'running')");
    auto b = add_run.binder();
    b(uuid).orNull(meta.batch_id)(meta.family)(params)(version)(config_name)(meta.planner)(settings);
    b(meta.family).orNull(meta.scene)(params)(static_cast<std::int64_t>(meta.seed))(meta.planner)(settings);
    b(meta.time_limit)(meta.memory_limit)(version)(meta.host.empty() ? hostName() : meta.host);
    b(meta.cpu_info.empty() ? cpuInfo() : meta.cpu_info)(isoNow());
    add_run.run();
    const std::int64_t run_id = sqlite3_last_insert_rowid(db);
    m.commitLocked();
    m.active[uuid] = Impl::ActiveRun{run_id, Clock::now(), nullptr};
  } catch (...) {
    m.rollbackLocked();
    throw;
  }
  return uuid;
}

std::unique_ptr<SqliteRecorder> ResultsDb::recorder(const std::string& uuid) { return recorder(uuid, {}); }

std::unique_ptr<SqliteRecorder> ResultsDb::recorder(const std::string& uuid, const RecorderOptions& options) {
  Impl& m = *impl_;
  m.requireWritable();
  std::lock_guard lock(m.mutex);
  auto it = m.active.find(uuid);
  DASH_THROW_UNLESS(it != m.active.end(), "run " + uuid + " was not begun by this process, or has finished");
  DASH_THROW_UNLESS(it->second.recorder == nullptr, "run " + uuid + " already has a recorder");
  std::unique_ptr<SqliteRecorder> recorder(new SqliteRecorder(m, uuid, it->second.run_id));
  it->second.recorder = recorder.get();
  m.run_states[it->second.run_id].progress_interval = options.progress_interval;
  return recorder;
}

void ResultsDb::finishRun(const std::string& uuid, const RunSummary& summary) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(summary.status != RunStatus::Running, "finishRun needs a final status, not 'running'");
  auto requireRunning = [&](std::int64_t run_id) {
    sql::Statement st(m.db.get(), "SELECT status FROM dash_runs WHERE id = ?");
    st.bind(1, run_id);
    st.step();
    DASH_THROW_UNLESS(st.columnText(0) == "running", "run " + uuid + " has already finished (" + st.columnText(0) + ")");
  };
  SqliteRecorder* recorder = nullptr;
  {
    std::lock_guard lock(m.mutex);
    requireRunning(runIdOf(m.db.get(), uuid));
    if (auto it = m.active.find(uuid); it != m.active.end()) recorder = it->second.recorder;
  }
  // The run's last events first: hand them over (outside the lock: the writer needs it) and wait.
  if (recorder != nullptr) recorder->handOver(true);
  m.waitDrained();

  std::lock_guard lock(m.mutex);
  const std::int64_t run_id = runIdOf(m.db.get(), uuid);
  requireRunning(run_id);
  std::optional<double> elapsed;
  auto it = m.active.find(uuid);
  if (it != m.active.end()) elapsed = std::chrono::duration<double>(Clock::now() - it->second.start).count();
  std::string recorder_error;
  const RunFigures* tally = nullptr;  // stands for the stored events only if the writer stored every one
  if (auto state = m.run_states.find(run_id); state != m.run_states.end()) {
    recorder_error = state->second.error;
    if (recorder_error.empty()) tally = &state->second.figures;
  }
  try {
    finishRunLocked(m, run_id, summary, elapsed, recorder_error, tally);
  } catch (...) {
    m.rollbackLocked();
    throw;
  }
  m.run_states.erase(run_id);
  if (it != m.active.end()) m.active.erase(it);
}

int ResultsDb::markInterrupted(const std::string& reason, RunStatus status) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(status != RunStatus::Running, "markInterrupted needs a final status");
  std::lock_guard lock(m.mutex);
  std::vector<std::int64_t> ids;
  sql::Statement st(m.db.get(), "SELECT id, uuid FROM dash_runs WHERE status = 'running' ORDER BY id");
  while (st.step()) {
    if (m.active.count(st.columnText(1)) == 0) ids.push_back(st.columnInt(0));
  }
  RunSummary summary{.status = status, .error = reason};
  try {
    for (std::int64_t id : ids) finishRunLocked(m, id, summary, std::nullopt, {});
  } catch (...) {
    m.rollbackLocked();
    throw;
  }
  return static_cast<int>(ids.size());
}

void ResultsDb::flush() {
  Impl& m = *impl_;
  std::vector<SqliteRecorder*> recorders;
  {
    std::lock_guard lock(m.mutex);
    for (auto& [uuid, run] : m.active) {
      if (run.recorder != nullptr) recorders.push_back(run.recorder);
    }
  }
  for (SqliteRecorder* r : recorders) r->handOver(false);
  m.waitDrained();
}

void ResultsDb::putBatch(const BatchRecord& batch) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(!batch.id.empty(), "a batch needs an id");
  const std::string spec = canonicalObject(batch.spec_json, "batch spec", false);
  std::lock_guard lock(m.mutex);
  sql::Statement st(m.db.get(),
                    "INSERT INTO dash_batches (id, name, spec, created, status) VALUES (?,?,?,?,?) ON CONFLICT(id) "
                    "DO UPDATE SET name = excluded.name, spec = excluded.spec, status = excluded.status");
  st.bind(1, batch.id).bind(2, batch.name).bind(3, spec).bind(4, batch.created.empty() ? isoNow() : batch.created);
  st.bind(5, batch.status).run();
}

void ResultsDb::setBatchStatus(const std::string& id, const std::string& status) {
  Impl& m = *impl_;
  m.requireWritable();
  std::lock_guard lock(m.mutex);
  sql::Statement st(m.db.get(), "UPDATE dash_batches SET status = ? WHERE id = ?");
  st.bind(1, status).bind(2, id).run();
  DASH_THROW_UNLESS(sqlite3_changes(m.db.get()) == 1, "no batch with id " + id);
}

void ResultsDb::addTag(const std::string& uuid, const std::string& tag) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(!tag.empty(), "a tag cannot be empty");
  std::lock_guard lock(m.mutex);
  sql::Statement st(m.db.get(), "INSERT OR IGNORE INTO dash_run_tags (run_id, tag) VALUES (?, ?)");
  st.bind(1, runIdOf(m.db.get(), uuid)).bind(2, tag).run();
}

void ResultsDb::removeTag(const std::string& uuid, const std::string& tag) {
  Impl& m = *impl_;
  m.requireWritable();
  std::lock_guard lock(m.mutex);
  sql::Statement st(m.db.get(), "DELETE FROM dash_run_tags WHERE run_id = ? AND tag = ?");
  st.bind(1, runIdOf(m.db.get(), uuid)).bind(2, tag).run();
}

void ResultsDb::setNote(const std::string& uuid, const std::string& note) {
  Impl& m = *impl_;
  m.requireWritable();
  std::lock_guard lock(m.mutex);
  sql::Statement st(m.db.get(), "UPDATE dash_runs SET note = ? WHERE id = ?");
  st.bindOrNull(1, note).bind(2, runIdOf(m.db.get(), uuid)).run();
}

void ResultsDb::refreshArenaViews() {
  Impl& m = *impl_;
  m.requireWritable();
  // Called from the constructor before other threads can see this object, and under the lock otherwise.
  dash::log::refreshArenaViews(m.db.get());
}

}  // namespace dash::log
