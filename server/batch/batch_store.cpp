#include "server/batch/batch_store.h"

#include <signal.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <sstream>

#include "engine/log/sqlite_util.h"

namespace dash::batch {

namespace sql = log::sql;

namespace {

constexpr const char* kBatchTables = R"sql(
CREATE TABLE IF NOT EXISTS dash_batch_runs (
  batch_id TEXT NOT NULL,
  run_key TEXT NOT NULL,
  ordinal INTEGER NOT NULL,
  spec TEXT NOT NULL,
  run_uuid TEXT,
  attempts INTEGER NOT NULL DEFAULT 0,
  PRIMARY KEY (batch_id, run_key)
) WITHOUT ROWID;
CREATE INDEX IF NOT EXISTS dash_batch_runs_uuid ON dash_batch_runs(run_uuid);
CREATE TABLE IF NOT EXISTS dash_batch_skipped (
  batch_id TEXT NOT NULL,
  run_key TEXT NOT NULL,
  reason TEXT NOT NULL,
  PRIMARY KEY (batch_id, run_key)
) WITHOUT ROWID;
CREATE TABLE IF NOT EXISTS dash_batch_runner (
  batch_id TEXT PRIMARY KEY,
  pid INTEGER NOT NULL,
  host TEXT NOT NULL,
  started TEXT NOT NULL,
  heartbeat REAL NOT NULL,
  workers INTEGER NOT NULL
);
)sql";

double unixNow() { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); }

bool tableExists(sqlite3* db, const std::string& name) {
  sql::Statement st(db, "SELECT 1 FROM sqlite_schema WHERE type = 'table' AND name = ?");
  st.bind(1, name);
  return st.step();
}

/// Runs `body` inside BEGIN IMMEDIATE ... COMMIT (ROLLBACK on an exception).
template <class F>
void transaction(sqlite3* db, F&& body) {
  sql::exec(db, "BEGIN IMMEDIATE");
  try {
    body();
    sql::exec(db, "COMMIT");
  } catch (...) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

}  // namespace

bool StoredRun::complete() const {
  if (!skipped.empty()) return true;
  if (!status) return false;
  if (*status == "running" || *status == "cancelled") return false;
  if (*status == "crashed" && error.rfind("interrupted:", 0) == 0) return false;
  return true;
}

double RunnerInfo::age() const { return unixNow() - heartbeat; }

bool RunnerInfo::alive() const {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) == 0 && host == name && pid > 0) {
    if (kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) return false;
  }
  return age() < kStaleHeartbeatSeconds;
}

struct BatchStore::Impl {
  sql::Connection db;
  bool has_tables = false;
  bool has_skipped = false;  ///< dash_batch_skipped exists (a file written before it may lack it)
  std::vector<std::string> run_tables;  ///< tables with a run_id column (event tables, tags)
};

BatchStore::BatchStore(const std::string& path, log::OpenMode mode) : impl_(new Impl) {
  try {
    const int flags = mode == log::OpenMode::ReadOnly ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE;
    impl_->db = sql::open(path, flags | SQLITE_OPEN_NOMUTEX);
    sqlite3* db = impl_->db.get();
    sqlite3_busy_timeout(db, 15000);
    DASH_THROW_UNLESS(tableExists(db, "dash_runs"), path + " is not a dashbench results database");
    if (mode == log::OpenMode::ReadWrite) sql::exec(db, kBatchTables);
    impl_->has_tables = tableExists(db, "dash_batch_runs");
    impl_->has_skipped = tableExists(db, "dash_batch_skipped");
    sql::Statement tables(db,
                          "SELECT m.name FROM sqlite_schema m, pragma_table_info(m.name) p "
                          "WHERE m.type = 'table' AND p.name = 'run_id' ORDER BY m.name");
    while (tables.step()) impl_->run_tables.push_back(tables.columnText(0));
  } catch (...) {
    delete impl_;
    throw;
  }
}

BatchStore::~BatchStore() { delete impl_; }

void BatchStore::addRuns(const std::string& batch_id, const std::vector<RunSpec>& runs) {
  sqlite3* db = impl_->db.get();
  transaction(db, [&] {
    {
      sql::Statement exists(db, "SELECT 1 FROM dash_batch_runs WHERE batch_id = ? LIMIT 1");
      exists.bind(1, batch_id);
      DASH_THROW_UNLESS(!exists.step(), "batch " + batch_id + " already has a stored run list");
    }
    sql::Statement insert(db, "INSERT INTO dash_batch_runs (batch_id, run_key, ordinal, spec) VALUES (?,?,?,?)");
    for (const RunSpec& r : runs) {
      insert.bind(1, batch_id).bind(2, r.key).bind(3, r.ordinal).bind(4, r.toJson());
      insert.run();
    }
  });
}

std::vector<StoredRun> BatchStore::runs(const std::string& batch_id) const {
  std::vector<StoredRun> out;
  if (!impl_->has_tables) return out;
  sql::Statement st(impl_->db.get(),
                    impl_->has_skipped
                        ? "SELECT b.spec, b.run_uuid, b.attempts, r.status, r.error, s.reason FROM dash_batch_runs b "
                          "LEFT JOIN dash_runs r ON r.uuid = b.run_uuid "
                          "LEFT JOIN dash_batch_skipped s ON s.batch_id = b.batch_id AND s.run_key = b.run_key "
                          "WHERE b.batch_id = ? ORDER BY b.ordinal"
                        : "SELECT b.spec, b.run_uuid, b.attempts, r.status, r.error, NULL FROM dash_batch_runs b "
                          "LEFT JOIN dash_runs r ON r.uuid = b.run_uuid WHERE b.batch_id = ? ORDER BY b.ordinal");
  st.bind(1, batch_id);
  while (st.step()) {
    StoredRun r;
    r.spec = RunSpec::fromJson(st.columnText(0));
    if (!st.isNull(1)) r.run_uuid = st.columnText(1);
    r.attempts = static_cast<int>(st.columnInt(2));
    if (!st.isNull(3)) r.status = st.columnText(3);
    if (!st.isNull(4)) r.error = st.columnText(4);
    if (!st.isNull(5)) r.skipped = st.columnText(5);
    out.push_back(std::move(r));
  }
  return out;
}

std::int64_t BatchStore::runCount(const std::string& batch_id) const {
  if (!impl_->has_tables) return 0;
  sql::Statement st(impl_->db.get(), "SELECT COUNT(*) FROM dash_batch_runs WHERE batch_id = ?");
  st.bind(1, batch_id);
  return st.step() ? st.columnInt(0) : 0;
}

BatchStore::Counts BatchStore::counts(const std::string& batch_id) const {
  Counts out;
  if (!impl_->has_tables) return out;
  // "Pending" is StoredRun::complete() negated, in SQL: not skipped, and no row, or a row that is
  // running, cancelled, or a crash closed by markInterrupted ("interrupted: ...").
  constexpr const char* kPending =
      "r.status IS NULL OR r.status IN ('running', 'cancelled') OR "
      "(r.status = 'crashed' AND substr(COALESCE(r.error, ''), 1, 12) = 'interrupted:')";
  const std::string skipped = impl_->has_skipped ? "s.reason IS NOT NULL" : "0";
  sql::Statement st(
      impl_->db.get(),
      "SELECT COUNT(*), COALESCE(SUM(CASE WHEN " + skipped + " THEN 0 WHEN " + kPending +
          " THEN 1 ELSE 0 END), 0), COALESCE(SUM(" + skipped +
          "), 0) FROM dash_batch_runs b "
          "LEFT JOIN dash_runs r ON r.uuid = b.run_uuid " +
          (impl_->has_skipped ? "LEFT JOIN dash_batch_skipped s ON s.batch_id = b.batch_id AND s.run_key = b.run_key "
                              : "") +
          "WHERE b.batch_id = ?");
  st.bind(1, batch_id);
  if (st.step()) {
    out.total = st.columnInt(0);
    out.pending = st.columnInt(1);
    out.skipped = st.columnInt(2);
  }
  return out;
}

void BatchStore::assignUuid(const std::string& batch_id, const std::string& key, const std::string& uuid) {
  sql::Statement st(
      impl_->db.get(),
      "UPDATE dash_batch_runs SET run_uuid = ?, attempts = attempts + 1 WHERE batch_id = ? AND run_key = ?");
  st.bind(1, uuid).bind(2, batch_id).bind(3, key).run();
  DASH_DEMAND_MSG(sqlite3_changes(impl_->db.get()) == 1, "no stored run " + key + " in batch " + batch_id);
}

void BatchStore::deleteRun(const std::string& uuid) {
  sqlite3* db = impl_->db.get();
  transaction(db, [&] {
    sql::Statement find(db, "SELECT id FROM dash_runs WHERE uuid = ?");
    find.bind(1, uuid);
    if (!find.step()) return;
    const std::int64_t id = find.columnInt(0);
    for (const std::string& table : impl_->run_tables) {
      sql::Statement del(db, "DELETE FROM " + sql::quoteIdentifier(table) + " WHERE run_id = ?");
      del.bind(1, id).run();
    }
    sql::Statement del(db, "DELETE FROM dash_runs WHERE id = ?");
    del.bind(1, id).run();
  });
}

int BatchStore::deleteOrphans(const std::string& batch_id) {
  std::vector<std::string> orphans;
  {
    sql::Statement st(impl_->db.get(),
                      "SELECT uuid FROM dash_runs WHERE batch_id = ? AND uuid NOT IN "
                      "(SELECT run_uuid FROM dash_batch_runs WHERE batch_id = ? AND run_uuid IS NOT NULL)");
    st.bind(1, batch_id).bind(2, batch_id);
    while (st.step()) orphans.push_back(st.columnText(0));
  }
  for (const auto& uuid : orphans) deleteRun(uuid);
  return static_cast<int>(orphans.size());
}

void BatchStore::markSkipped(const std::string& batch_id, const std::string& key, const std::string& reason) {
  sqlite3* db = impl_->db.get();
  std::string uuid;
  {
    sql::Statement st(db, "SELECT run_uuid FROM dash_batch_runs WHERE batch_id = ? AND run_key = ?");
    st.bind(1, batch_id).bind(2, key);
    DASH_THROW_UNLESS(st.step(), "batch " + batch_id + " has no run " + key);
    if (!st.isNull(0)) uuid = st.columnText(0);
  }
  if (!uuid.empty()) deleteRun(uuid);
  sql::Statement insert(db, "INSERT OR REPLACE INTO dash_batch_skipped (batch_id, run_key, reason) VALUES (?,?,?)");
  insert.bind(1, batch_id).bind(2, key).bind(3, reason).run();
}

void BatchStore::setScene(const std::string& uuid, const std::string& scene) {
  sql::Statement st(impl_->db.get(), "UPDATE dash_runs SET scene = ? WHERE uuid = ?");
  st.bind(1, scene).bind(2, uuid).run();
}

void BatchStore::setRunner(const std::string& batch_id, const RunnerInfo& info) {
  sql::Statement st(impl_->db.get(),
                    "INSERT OR REPLACE INTO dash_batch_runner (batch_id, pid, host, started, heartbeat, workers) "
                    "VALUES (?,?,?,?,?,?)");
  st.bind(1, batch_id).bind(2, info.pid).bind(3, info.host).bind(4, info.started).bind(5, unixNow());
  st.bind(6, info.workers).run();
}

void BatchStore::heartbeat(const std::string& batch_id) {
  sql::Statement st(impl_->db.get(), "UPDATE dash_batch_runner SET heartbeat = ? WHERE batch_id = ?");
  st.bind(1, unixNow()).bind(2, batch_id).run();
}

void BatchStore::clearRunner(const std::string& batch_id) {
  sql::Statement st(impl_->db.get(), "DELETE FROM dash_batch_runner WHERE batch_id = ?");
  st.bind(1, batch_id).run();
}

std::optional<RunnerInfo> BatchStore::runner(const std::string& batch_id) const {
  if (!impl_->has_tables) return std::nullopt;
  sql::Statement st(impl_->db.get(),
                    "SELECT pid, host, started, heartbeat, workers FROM dash_batch_runner WHERE batch_id = ?");
  st.bind(1, batch_id);
  if (!st.step()) return std::nullopt;
  RunnerInfo info;
  info.pid = st.columnInt(0);
  info.host = st.columnText(1);
  info.started = st.columnText(2);
  info.heartbeat = st.columnDouble(3);
  info.workers = static_cast<int>(st.columnInt(4));
  return info;
}

std::vector<BatchInfo> listBatchInfo(const std::string& db_path, const std::string& batch_id) {
  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const BatchStore store(db_path, log::OpenMode::ReadOnly);
  std::vector<BatchInfo> out;
  for (const log::BatchRecord& b : db.listBatches()) {
    if (!batch_id.empty() && b.id != batch_id) continue;
    BatchInfo info;
    info.record = b;
    info.status = b.status;
    info.runner = store.runner(b.id);
    if (b.status == "running" && (!info.runner || !info.runner->alive())) {
      info.status = "interrupted";
    }
    const log::SqlRows rows =
        db.select("SELECT status, COUNT(*) FROM dash_runs WHERE batch_id = ? GROUP BY status", {b.id});
    for (const auto& row : rows.rows) {
      info.by_status[std::get<std::string>(row[0])] = std::get<std::int64_t>(row[1]);
    }
    const BatchStore::Counts counts = store.counts(b.id);
    info.total = counts.total;
    info.pending = counts.pending;
    if (counts.skipped > 0) info.by_status["skipped"] = counts.skipped;
    out.push_back(std::move(info));
  }
  DASH_THROW_UNLESS(batch_id.empty() || !out.empty(), "no batch " + batch_id + " in " + db_path);
  return out;
}

std::string formatBatchInfo(const std::vector<BatchInfo>& batches) {
  if (batches.empty()) return "no batches\n";
  std::vector<std::vector<std::string>> rows = {{"batch", "name", "status", "runs", "solved", "timeout", "infeasible",
                                                 "crashed", "cancelled", "skipped", "running", "pending", "created"}};
  for (const BatchInfo& b : batches) {
    auto count = [&](const char* s) {
      const auto it = b.by_status.find(s);
      return std::to_string(it == b.by_status.end() ? 0 : it->second);
    };
    // 'running' rows of a batch whose runner is gone are runs to re-run, not live ones. The columns add up
    // to the runs: pending is what has not started (b.pending also holds the live runs, not final yet).
    const auto live = b.status == "running" ? b.by_status.find("running") : b.by_status.end();
    const std::int64_t running = live == b.by_status.end() ? 0 : live->second;
    rows.push_back({b.record.id, b.record.name, b.status, std::to_string(b.total), count("solved"), count("timeout"),
                    count("infeasible"), count("crashed"), count("cancelled"), count("skipped"),
                    std::to_string(running), std::to_string(std::max<std::int64_t>(0, b.pending - running)),
                    b.record.created});
  }
  std::vector<std::size_t> width(rows[0].size(), 0);
  for (const auto& r : rows) {
    for (std::size_t i = 0; i < r.size(); ++i) width[i] = std::max(width[i], r[i].size());
  }
  std::ostringstream out;
  for (const auto& r : rows) {
    std::string line;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const std::string pad(width[i] - r[i].size(), ' ');
      const bool left = i < 3 || i + 1 == r.size();  // id, name, status, created
      line += (i == 0 ? "" : "  ") + (left ? r[i] + pad : pad + r[i]);
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    out << line << "\n";
  }
  return out.str();
}

}  // namespace dash::batch
