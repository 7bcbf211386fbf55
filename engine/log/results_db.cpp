#include "engine/log/results_db.h"

#include <sqlite3.h>
#include <sys/resource.h>
#include <unistd.h>

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

#ifndef DASHBENCH_VERSION
#define DASHBENCH_VERSION "0.0.0"
#endif

namespace dash::log {
namespace {

constexpr std::array<const char*, 6> kStatusNames = {"running", "solved", "timeout", "infeasible", "crashed",
                                                     "cancelled"};

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

std::string newUuid() {
  std::random_device device;
  std::array<unsigned char, 16> bytes{};
  for (std::size_t i = 0; i < bytes.size(); i += 4) {
    const std::uint32_t r = device();
    for (std::size_t k = 0; k < 4; ++k) bytes[i + k] = static_cast<unsigned char>(r >> (8 * k));
  }
  bytes[6] = static_cast<unsigned char>((bytes[6] & 0x0f) | 0x40);  // version 4
  bytes[8] = static_cast<unsigned char>((bytes[8] & 0x3f) | 0x80);  // RFC 4122 variant
  std::string out;
  char hex[3];
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i == 4 || i == 6 || i == 8 || i == 10) out += '-';
    std::snprintf(hex, sizeof(hex), "%02x", bytes[i]);
    out += hex;
  }
  return out;
}

std::string hostName() {
  char name[256] = {};
  if (gethostname(name, sizeof(name) - 1) != 0) return "unknown";
  return name;
}

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

int layerIndex(const std::string& name) {
  for (int i = 0; i < kLayerCount; ++i) {
    if (name == kLayerNames[i]) return i;
  }
  return -1;
}

template <std::size_t N>
int nameIndex(const std::array<const char*, N>& names, const std::string& name) {
  for (std::size_t i = 0; i < N; ++i) {
    if (name == names[i]) return static_cast<int>(i);
  }
  return -1;
}

// What a run's stored events say, for the figures a summary leaves unset.
struct Derived {
  RepresentationSizes sizes;
  PhaseTotals phases{};
  std::array<std::int64_t, kConstraintKindCount> constraints{};
  std::int64_t active_constraints = 0;
  std::int64_t expansions = 0;
  std::map<std::string, std::int64_t> counters;
  std::int64_t max_iteration = 0;
  double last_t = 0.0;
  std::int64_t events = 0;

  void see(const sql::Statement& st, int count_col, int iteration_col, int t_col) {
    events += st.columnInt(count_col);
    max_iteration = std::max(max_iteration, st.columnInt(iteration_col));
    last_t = std::max(last_t, st.columnDouble(t_col));
  }
};

Derived deriveFromTables(sqlite3* db, std::int64_t run_id) {
  Derived d;
  sql::Statement ev(db,
                    "SELECT layer, kind, SUM(CASE change WHEN 'added' THEN 1 ELSE -1 END), COUNT(*), MAX(iteration), "
                    "MAX(t) FROM dash_events WHERE run_id = ? GROUP BY layer, kind");
  ev.bind(1, run_id);
  while (ev.step()) {
    const int layer = layerIndex(ev.columnText(0));
    if (layer >= 0) (ev.columnText(1) == "vertex" ? d.sizes.vertices : d.sizes.hyperarcs)[layer] = ev.columnInt(2);
    d.see(ev, 3, 4, 5);
  }
  sql::Statement ph(db, "SELECT phase, SUM(duration), COUNT(*), MAX(iteration), MAX(t_end) FROM dash_phases "
                        "WHERE run_id = ? GROUP BY phase");
  ph.bind(1, run_id);
  while (ph.step()) {
    if (const int p = nameIndex(kPhaseNames, ph.columnText(0)); p >= 0) d.phases[p] = ph.columnDouble(1);
    d.see(ph, 2, 3, 4);
  }
  sql::Statement co(db, "SELECT kind, SUM(action = 'created'), SUM(CASE action WHEN 'created' THEN 1 ELSE -1 END), "
                        "COUNT(*), MAX(iteration), MAX(t) FROM dash_constraints WHERE run_id = ? GROUP BY kind");
  co.bind(1, run_id);
  while (co.step()) {
    if (const int k = nameIndex(kConstraintKindNames, co.columnText(0)); k >= 0) d.constraints[k] = co.columnInt(1);
    d.active_constraints += co.columnInt(2);
    d.see(co, 3, 4, 5);
  }
  sql::Statement ex(db, "SELECT COUNT(*), MAX(iteration), MAX(t) FROM dash_expansions WHERE run_id = ?");
  ex.bind(1, run_id);
  if (ex.step()) {
    d.expansions = ex.columnInt(0);
    d.see(ex, 0, 1, 2);
  }
  // SQLite takes the bare column `value` from the row holding MAX(seq): the latest value.
  sql::Statement cn(db, "SELECT name, value, MAX(seq) FROM dash_counters WHERE run_id = ? GROUP BY name");
  cn.bind(1, run_id);
  while (cn.step()) d.counters[cn.columnText(0)] = cn.columnInt(1);
  sql::Statement cs(db, "SELECT COUNT(*), MAX(iteration), MAX(t) FROM dash_counters WHERE run_id = ?");
  cs.bind(1, run_id);
  if (cs.step()) d.see(cs, 0, 1, 2);
  return d;
}

std::optional<std::int64_t> counterOf(const Derived& d, const char* name) {
  auto it = d.counters.find(name);
  if (it == d.counters.end()) return std::nullopt;
  return it->second;
}

// Writes a run's outcome: the summary, with unset figures derived from its events.
void finishLocked(ResultsDb::Impl& m, std::int64_t run_id, const RunSummary& s, std::optional<double> elapsed,
                  const std::string& recorder_error) {
  m.commitLocked();
  const Derived d = deriveFromTables(m.db.get(), run_id);
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
  b(s.makespan)(s.path_length)(s.peak_memory_mb).orNull(s.plan_json)(d.events)(run_id);
  up.run();

  sql::Statement& pr = m.insert_progress;
  pr.bind(1, run_id).bind(2, total).bind(3, s.iterations.value_or(d.max_iteration));
  for (int l = 0; l < kLayerCount; ++l) pr.bind(4 + 2 * l, sizes.vertices[l]).bind(5 + 2 * l, sizes.hyperarcs[l]);
  pr.bind(12, roadmap_vertices.value_or(0)).bind(13, roadmap_edges.value_or(0)).bind(14, d.active_constraints);
  pr.bind(15, checks.value_or(0));
  pr.run();
  m.commitLocked();
}

std::int64_t runIdOf(sqlite3* db, const std::string& uuid) {
  sql::Statement st(db, "SELECT id FROM dash_runs WHERE uuid = ?");
  st.bind(1, uuid);
  DASH_THROW_UNLESS(st.step(), "no run with uuid " + uuid);
  return st.columnInt(0);
}

std::vector<std::string> splitTags(const std::string& joined) {
  std::vector<std::string> tags;
  std::size_t start = 0;
  while (!joined.empty() && start <= joined.size()) {
    const std::size_t end = joined.find('\x1f', start);
    tags.push_back(joined.substr(start, end == std::string::npos ? std::string::npos : end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return tags;
}

}  // namespace

const char* toString(RunStatus status) { return kStatusNames[static_cast<int>(status)]; }

RunStatus parseRunStatus(const std::string& name) {
  const int i = nameIndex(kStatusNames, name);
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
  pending = 0;
  transaction_start = Clock::now();
}

void ResultsDb::Impl::afterWriteLocked() {
  ++pending;
  if (pending >= options.commit_every_events ||
      std::chrono::duration<double>(Clock::now() - transaction_start).count() >= options.commit_every_seconds) {
    commitLocked();
  }
}

void ResultsDb::Impl::commitLocked() {
  if (!in_transaction) return;
  in_transaction = false;
  pending = 0;
  try {
    sql::exec(db.get(), "COMMIT");
  } catch (...) {
    rollbackLocked();
    throw;
  }
}

void ResultsDb::Impl::rollbackLocked() noexcept {
  in_transaction = false;
  pending = 0;
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
  m.insert_event = sql::Statement(db, "INSERT INTO dash_events (run_id, seq, t, iteration, layer, kind, change, "
                                      "arc_type, element_id, head, tail, label) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
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
          "motion_extended_hyperarcs, roadmap_vertices, roadmap_edges, constraints, collision_checks) "
          "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
}

ResultsDb::~ResultsDb() {
  Impl& m = *impl_;
  std::lock_guard lock(m.mutex);
  for (auto& [uuid, run] : m.active) {
    if (run.recorder != nullptr) run.recorder->db_ = nullptr;
  }
  try {
    m.commitLocked();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dashbench: could not commit the last events to %s: %s\n", m.path.c_str(), e.what());
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
  const std::string version = meta.code_version.empty() ? DASHBENCH_VERSION : meta.code_version;
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
  std::unique_ptr<SqliteRecorder> recorder(new SqliteRecorder(m, uuid, it->second.run_id, options));
  it->second.recorder = recorder.get();
  return recorder;
}

void ResultsDb::finishRun(const std::string& uuid, const RunSummary& summary) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(summary.status != RunStatus::Running, "finishRun needs a final status, not 'running'");
  std::lock_guard lock(m.mutex);
  const std::int64_t run_id = runIdOf(m.db.get(), uuid);
  {
    sql::Statement st(m.db.get(), "SELECT status FROM dash_runs WHERE id = ?");
    st.bind(1, run_id);
    st.step();
    DASH_THROW_UNLESS(st.columnText(0) == "running", "run " + uuid + " has already finished (" + st.columnText(0) + ")");
  }
  std::optional<double> elapsed;
  auto it = m.active.find(uuid);
  if (it != m.active.end()) elapsed = std::chrono::duration<double>(Clock::now() - it->second.start).count();
  try {
    const std::string recorder_error =
        it != m.active.end() && it->second.recorder != nullptr ? it->second.recorder->error_ : std::string();
    finishLocked(m, run_id, summary, elapsed, recorder_error);
  } catch (...) {
    m.rollbackLocked();
    throw;
  }
  if (it != m.active.end()) {
    if (it->second.recorder != nullptr) it->second.recorder->finished_ = true;
    m.active.erase(it);
  }
}

int ResultsDb::markInterrupted(const std::string& reason, RunStatus status) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(status != RunStatus::Running, "markInterrupted needs a final status");
  std::lock_guard lock(m.mutex);
  m.commitLocked();
  std::vector<std::int64_t> ids;
  sql::Statement st(m.db.get(), "SELECT id, uuid FROM dash_runs WHERE status = 'running' ORDER BY id");
  while (st.step()) {
    if (m.active.count(st.columnText(1)) == 0) ids.push_back(st.columnInt(0));
  }
  RunSummary summary{.status = status, .error = reason};
  try {
    for (std::int64_t id : ids) finishLocked(m, id, summary, std::nullopt, {});
  } catch (...) {
    m.rollbackLocked();
    throw;
  }
  return static_cast<int>(ids.size());
}

void ResultsDb::flush() {
  std::lock_guard lock(impl_->mutex);
  impl_->commitLocked();
}

void ResultsDb::putBatch(const BatchRecord& batch) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(!batch.id.empty(), "a batch needs an id");
  const std::string spec = canonicalObject(batch.spec_json, "batch spec", false);
  std::lock_guard lock(m.mutex);
  m.commitLocked();
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
  m.commitLocked();
  sql::Statement st(m.db.get(), "UPDATE dash_batches SET status = ? WHERE id = ?");
  st.bind(1, status).bind(2, id).run();
  DASH_THROW_UNLESS(sqlite3_changes(m.db.get()) == 1, "no batch with id " + id);
}

void ResultsDb::addTag(const std::string& uuid, const std::string& tag) {
  Impl& m = *impl_;
  m.requireWritable();
  DASH_THROW_UNLESS(!tag.empty(), "a tag cannot be empty");
  std::lock_guard lock(m.mutex);
  m.commitLocked();
  sql::Statement st(m.db.get(), "INSERT OR IGNORE INTO dash_run_tags (run_id, tag) VALUES (?, ?)");
  st.bind(1, runIdOf(m.db.get(), uuid)).bind(2, tag).run();
}

void ResultsDb::removeTag(const std::string& uuid, const std::string& tag) {
  Impl& m = *impl_;
  m.requireWritable();
  std::lock_guard lock(m.mutex);
  m.commitLocked();
  sql::Statement st(m.db.get(), "DELETE FROM dash_run_tags WHERE run_id = ? AND tag = ?");
  st.bind(1, runIdOf(m.db.get(), uuid)).bind(2, tag).run();
}

void ResultsDb::setNote(const std::string& uuid, const std::string& note) {
  Impl& m = *impl_;
  m.requireWritable();
  std::lock_guard lock(m.mutex);
  m.commitLocked();
  sql::Statement st(m.db.get(), "UPDATE dash_runs SET note = ? WHERE id = ?");
  st.bindOrNull(1, note).bind(2, runIdOf(m.db.get(), uuid)).run();
}

void ResultsDb::refreshArenaViews() {
  Impl& m = *impl_;
  m.requireWritable();
  // Called from the constructor before other threads can see this object, and under the lock otherwise.
  dash::log::refreshArenaViews(m.db.get());
}

std::vector<RunRecord> ResultsDb::listRuns(const RunFilter& filter) const {
  std::string sql = std::string("SELECT ") + kRunSelectColumns + (filter.include_plan ? ", r.plan" : ", NULL") +
                    " FROM dash_runs r WHERE 1";
  std::vector<SqlValue> params;
  auto where = [&](const char* clause, SqlValue value) {
    sql += clause;
    params.push_back(std::move(value));
  };
  if (!filter.batch_id.empty()) where(" AND r.batch_id = ?", filter.batch_id);
  if (filter.status) where(" AND r.status = ?", std::string(toString(*filter.status)));
  if (!filter.family.empty()) where(" AND r.family = ?", filter.family);
  if (!filter.planner.empty()) where(" AND r.planner = ?", filter.planner);
  if (!filter.uuids.empty()) {
    sql += " AND r.uuid IN (";
    for (std::size_t i = 0; i < filter.uuids.size(); ++i) {
      sql += i == 0 ? "?" : ",?";
      params.emplace_back(filter.uuids[i]);
    }
    sql += ")";
  }
  sql += filter.newest_first ? " ORDER BY r.id DESC" : " ORDER BY r.id";
  where(" LIMIT ?", filter.limit);
  where(" OFFSET ?", filter.offset);

  std::lock_guard lock(impl_->mutex);
  sql::Statement st(impl_->db.get(), sql);
  for (std::size_t i = 0; i < params.size(); ++i) st.bind(static_cast<int>(i) + 1, params[i]);
  std::vector<RunRecord> runs;
  while (st.step()) {
    RunRecord r = readRunRecord(st);
    r.tags = splitTags(st.isNull(kRunSelectColumnCount - 1) ? "" : st.columnText(kRunSelectColumnCount - 1));
    if (filter.include_plan && !st.isNull(kRunSelectColumnCount)) r.summary.plan_json = st.columnText(kRunSelectColumnCount);
    runs.push_back(std::move(r));
  }
  return runs;
}

std::optional<RunRecord> ResultsDb::getRun(const std::string& uuid) const {
  auto runs = listRuns(RunFilter{.uuids = {uuid}, .limit = 1, .include_plan = true});
  if (runs.empty()) return std::nullopt;
  return std::move(runs.front());
}

std::vector<BatchRecord> ResultsDb::listBatches() const {
  std::lock_guard lock(impl_->mutex);
  sql::Statement st(impl_->db.get(), "SELECT id, name, spec, created, status FROM dash_batches ORDER BY created, id");
  std::vector<BatchRecord> out;
  while (st.step()) {
    out.push_back({st.columnText(0), st.columnText(1), st.columnText(2), st.columnText(3), st.columnText(4)});
  }
  return out;
}

DbInfo ResultsDb::info() const {
  std::lock_guard lock(impl_->mutex);
  sqlite3* db = impl_->db.get();
  DbInfo info;
  info.path = impl_->path;
  info.schema_version = readSchemaVersion(db);
  sql::Statement st(db, "SELECT status, COUNT(*) FROM dash_runs GROUP BY status ORDER BY status");
  while (st.step()) {
    info.runs_by_status[st.columnText(0)] = st.columnInt(1);
    info.runs += st.columnInt(1);
  }
  info.experiments = sql::selectInt(db, "SELECT COUNT(*) FROM dash_experiments");
  info.planner_configs = sql::selectInt(db, "SELECT COUNT(*) FROM dash_planner_configs");
  info.batches = sql::selectInt(db, "SELECT COUNT(*) FROM dash_batches");
  info.events = sql::selectInt(db,
                               "SELECT (SELECT COUNT(*) FROM dash_events) + (SELECT COUNT(*) FROM dash_constraints) + "
                               "(SELECT COUNT(*) FROM dash_expansions) + (SELECT COUNT(*) FROM dash_phases) + "
                               "(SELECT COUNT(*) FROM dash_counters)");
  return info;
}

SqlRows ResultsDb::select(const std::string& sql, const std::vector<SqlValue>& params) const {
  std::lock_guard lock(impl_->mutex);
  return sql::selectRows(impl_->db.get(), sql, params);
}

}  // namespace dash::log
