#include "server/http/db_watcher.h"

#include <chrono>
#include <cstdio>

#include "engine/log/results_db.h"
#include "server/http/api_json.h"

namespace dash::http {

namespace {

constexpr const char* kRunFields =
    "SELECT r.id, r.uuid, r.batch_id, r.status, r.planner, c.name, r.family, r.params, r.seed, r.total_time "
    "FROM dash_runs r LEFT JOIN dash_planner_configs c ON c.id = r.planner_config_id";

Json runMessage(const log::SqlRows& rows, std::size_t i) {
  const auto& r = rows.rows[i];
  return {{"uuid", toJson(r[1])},
          {"batch", toJson(r[2])},
          {"status", toJson(r[3])},
          {"planner", toJson(r[4])},
          {"config", toJson(r[5])},
          {"family", toJson(r[6])},
          {"params", std::holds_alternative<std::string>(r[7]) ? parseStored(std::get<std::string>(r[7])) : Json()},
          {"seed", toJson(r[8])},
          {"total_time", toJson(r[9])}};
}

}  // namespace

DbWatcher::DbWatcher(std::string db_path, EventHub& hub, double period_seconds)
    : db_path_(std::move(db_path)), hub_(hub), period_(period_seconds) {
  thread_ = std::thread([this] { loop(); });
}

DbWatcher::~DbWatcher() { stop(); }

void DbWatcher::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void DbWatcher::loop() {
  const auto period = std::chrono::duration<double>(period_);
  std::string last_error;
  while (true) {
    try {
      const log::ResultsDb db(db_path_, log::OpenMode::ReadOnly);
      poll(db);
      last_error.clear();
    } catch (const std::exception& e) {
      // A busy or briefly missing file: report once, keep polling.
      if (last_error != e.what())
        std::fprintf(stderr, "dashbench serve: watching %s: %s\n", db_path_.c_str(), e.what());
      last_error = e.what();
    }
    std::unique_lock lock(mutex_);
    if (cv_.wait_for(lock, period, [&] { return stopping_; })) return;
  }
}

void DbWatcher::poll(const log::ResultsDb& db) {
  if (last_id_ < 0) {
    // Start from now: the page loads the existing runs itself.
    const log::SqlRows max = db.select("SELECT COALESCE(max(id), 0) FROM dash_runs");
    last_id_ = std::get<std::int64_t>(max.rows[0][0]);
    const log::SqlRows running = db.select(std::string(kRunFields) + " WHERE r.status = 'running'");
    for (const auto& row : running.rows) watched_[std::get<std::string>(row[1])] = "running";
  }
  // New runs, runs running now, and runs we saw running (they may have finished or been replaced).
  std::string sql = std::string(kRunFields) + " WHERE r.id > ? OR r.status = 'running'";
  std::vector<log::SqlValue> params = {last_id_};
  for (const auto& [uuid, status] : watched_) {
    sql += " OR r.uuid = ?";
    params.emplace_back(uuid);
  }
  const log::SqlRows rows = db.select(sql, params);
  std::map<std::string, std::string> still_running;
  for (std::size_t i = 0; i < rows.rows.size(); ++i) {
    const auto& r = rows.rows[i];
    const std::int64_t id = std::get<std::int64_t>(r[0]);
    const std::string uuid = std::get<std::string>(r[1]);
    const std::string status = std::get<std::string>(r[3]);
    last_id_ = std::max(last_id_, id);
    const auto seen = watched_.find(uuid);
    if (seen == watched_.end() || seen->second != status) hub_.publish("run", uuid, jsonText(runMessage(rows, i)));
    if (status == "running") still_running[uuid] = status;
  }
  watched_ = still_running;

  // Live sizes of the running runs: their latest progress snapshot (with a long phase's progress:
  // conflict resolution's steps scheduled of the plan's) and event count.
  std::map<std::string, std::string> sizes;
  for (const auto& [uuid, status] : watched_) {
    const log::SqlRows p = db.select(
        "SELECT p.t, p.iteration, p.task_vertices, p.task_hyperarcs, p.task_extended_vertices, "
        "p.task_extended_hyperarcs,"
        " p.motion_vertices, p.motion_hyperarcs, p.motion_extended_vertices, p.motion_extended_hyperarcs,"
        " p.roadmap_vertices, p.roadmap_edges, p.constraints, p.collision_checks, p.progress_phase, p.progress_done,"
        " p.progress_total, p.progress_rate, p.progress_current,"
        " (SELECT count(*) FROM dash_events e WHERE e.run_id = r.id) + (SELECT count(*) FROM dash_constraints k WHERE"
        " k.run_id = r.id) AS events"
        " FROM dash_runs r LEFT JOIN dash_progress p ON p.run_id = r.id WHERE r.uuid = ? ORDER BY p.t DESC LIMIT 1",
        {uuid});
    if (p.rows.empty()) continue;
    Json j = rowObject(p, 0);
    j["uuid"] = uuid;
    std::string text = jsonText(j);
    const auto old = sizes_.find(uuid);
    if (old == sizes_.end() || old->second != text) hub_.publish("sizes", uuid, text);
    sizes[uuid] = std::move(text);
  }
  sizes_ = std::move(sizes);

  // The batch list: statuses and counts per status (cheap; the page refetches details on change).
  const log::SqlRows b = db.select(
      "SELECT b.id, b.status, (SELECT group_concat(s, ',') FROM (SELECT status || ':' || count(*) AS s FROM dash_runs"
      " WHERE batch_id = b.id GROUP BY status)) FROM dash_batches b ORDER BY b.id");
  std::string fingerprint;
  for (const auto& row : b.rows) {
    for (const auto& v : row)
      fingerprint += (std::holds_alternative<std::string>(v) ? std::get<std::string>(v) : "") + "|";
    fingerprint += "\n";
  }
  if (have_fingerprint_ && fingerprint != batches_fingerprint_) hub_.publish("batches", "", "{}");
  batches_fingerprint_ = std::move(fingerprint);
  have_fingerprint_ = true;
}

}  // namespace dash::http
