#include "engine/log/dispatch_store.h"

#include <sqlite3.h>

#include <cstdio>
#include <ctime>
#include <mutex>

#include "engine/log/results_schema.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

namespace {

constexpr const char* kSelectDispatch =
    "SELECT id, created, started, ended, state, reason, run_uuid, scene, planner, requested_by, client, time_scale, "
    "duration, elapsed, preflight, execution FROM dash_dispatches";

DispatchRecord readDispatch(const sql::Statement& st) {
  DispatchRecord r;
  int i = 0;
  auto text = [&] {
    const int c = i++;
    return st.isNull(c) ? std::string() : st.columnText(c);
  };
  auto number = [&] {
    const int c = i++;
    return st.isNull(c) ? 0.0 : st.columnDouble(c);
  };
  r.id = text();
  r.created = text();
  r.started = text();
  r.ended = text();
  r.state = text();
  r.reason = text();
  r.run_uuid = text();
  r.scene = text();
  r.planner = text();
  r.requested_by = text();
  r.client = text();
  r.time_scale = number();
  r.duration = number();
  r.elapsed = number();
  r.preflight = text();
  r.execution = text();
  if (r.execution.empty()) r.execution = "timed";
  return r;
}

}  // namespace

std::string isoTimeFromUnixMillis(std::int64_t unix_ms) {
  const std::time_t seconds = static_cast<std::time_t>(unix_ms / 1000);
  std::tm tm{};
  gmtime_r(&seconds, &tm);
  char text[64];
  std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d.%03dZ", tm.tm_year + 1900, tm.tm_mon + 1,
                tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec, static_cast<int>(unix_ms % 1000));
  return text;
}

struct DispatchStore::Impl {
  sql::Connection db;
  mutable std::mutex mutex;  ///< guards `db`
  bool writable = false;

  void readArms(DispatchRecord& r) const {
    sql::Statement st(db.get(),
                      "SELECT robot, driver, status, result, result_code, message, duration, max_deviation, samples, "
                      "segments FROM dash_dispatch_arms WHERE dispatch_id = ? ORDER BY ordinal");
    st.bind(1, r.id);
    while (st.step()) {
      DispatchArmRecord a;
      a.robot = st.columnText(0);
      a.driver = st.isNull(1) ? "" : st.columnText(1);
      a.status = st.isNull(2) ? "" : st.columnText(2);
      a.result = st.columnText(3);
      a.result_code = static_cast<int>(st.columnOptInt(4).value_or(0));
      a.message = st.isNull(5) ? "" : st.columnText(5);
      a.duration = st.columnOptDouble(6).value_or(0.0);
      a.max_deviation = st.columnOptDouble(7).value_or(0.0);
      a.samples = static_cast<int>(st.columnOptInt(8).value_or(0));
      a.segments = st.isNull(9) ? "" : st.columnText(9);
      r.arms.push_back(std::move(a));
    }
  }
};

DispatchStore::DispatchStore(const std::string& path, OpenMode mode) : impl_(std::make_unique<Impl>()) {
  // ResultsDb creates the file, sets WAL mode and migrates; this store only adds a connection.
  if (mode == OpenMode::ReadWrite) {
    const ResultsDb created(path, OpenMode::ReadWrite);
  }
  impl_->writable = mode == OpenMode::ReadWrite;
  impl_->db = sql::open(path, (impl_->writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY) | SQLITE_OPEN_NOMUTEX);
  sqlite3_busy_timeout(impl_->db.get(), 15000);
  checkSchemaReadable(impl_->db.get(), path);
}

DispatchStore::~DispatchStore() = default;

void DispatchStore::save(const DispatchRecord& r) {
  DASH_THROW_UNLESS(impl_->writable, "the dispatch store was opened read-only");
  DASH_THROW_UNLESS(!r.id.empty(), "dispatch record: empty id");
  std::lock_guard<std::mutex> lock(impl_->mutex);
  sqlite3* db = impl_->db.get();
  sql::exec(db, "BEGIN IMMEDIATE");
  try {
    sql::Statement up(db,
                      "INSERT OR REPLACE INTO dash_dispatches (id, created, started, ended, state, reason, run_uuid, "
                      "scene, planner, requested_by, client, time_scale, duration, elapsed, preflight, execution) "
                      "VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)");
    auto b = up.binder();
    b(r.id)(r.created).orNull(r.started).orNull(r.ended)(r.state).orNull(r.reason).orNull(r.run_uuid).orNull(r.scene);
    b.orNull(r.planner).orNull(r.requested_by).orNull(r.client)(r.time_scale)(r.duration)(r.elapsed).orNull(r.preflight)(r.execution);
    up.run();
    sql::Statement del(db, "DELETE FROM dash_dispatch_arms WHERE dispatch_id = ?");
    del.bind(1, r.id).run();
    sql::Statement arm(db,
                       "INSERT INTO dash_dispatch_arms (dispatch_id, robot, ordinal, driver, status, result, "
                       "result_code, message, duration, max_deviation, samples, segments) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
    int ordinal = 0;
    for (const DispatchArmRecord& a : r.arms) {
      auto ab = arm.binder();
      ab(r.id)(a.robot)(ordinal++).orNull(a.driver).orNull(a.status)(a.result)(a.result_code).orNull(a.message)(a.duration);
      ab(a.max_deviation)(a.samples).orNull(a.segments);
      arm.run();
    }
    sql::exec(db, "COMMIT");
  } catch (...) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<DispatchRecord> DispatchStore::list(int limit, int offset) const {
  DASH_THROW_UNLESS(limit >= 0 && offset >= 0, "dispatch list: limit and offset must not be negative");
  std::lock_guard<std::mutex> lock(impl_->mutex);
  sql::Statement st(impl_->db.get(), std::string(kSelectDispatch) + " ORDER BY created DESC, id DESC LIMIT ? OFFSET ?");
  st.bind(1, limit).bind(2, offset);
  std::vector<DispatchRecord> out;
  while (st.step()) out.push_back(readDispatch(st));
  for (DispatchRecord& r : out) impl_->readArms(r);
  return out;
}

std::optional<DispatchRecord> DispatchStore::get(const std::string& id) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  sql::Statement st(impl_->db.get(), std::string(kSelectDispatch) + " WHERE id = ?");
  st.bind(1, id);
  if (!st.step()) return std::nullopt;
  DispatchRecord r = readDispatch(st);
  impl_->readArms(r);
  return r;
}

std::int64_t DispatchStore::count() const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return sql::selectInt(impl_->db.get(), "SELECT COUNT(*) FROM dash_dispatches");
}

}  // namespace dash::log
