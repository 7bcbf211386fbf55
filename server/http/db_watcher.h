#pragma once
// DbWatcher: polls the results database for what the dashboard shows live, whoever writes it (this
// server's batches or a `dashbench batch run` in a terminal), and publishes it to the EventHub:
//   "run"     a run appeared or changed status: {"uuid", "batch", "status", "planner", "config",
//             "family", "params", "seed", "total_time"}
//   "sizes"   a running run's representation sizes grew: its latest progress snapshot
//             {"uuid", "t", "iteration", "task_vertices", ..., "constraints", "collision_checks", "events"}
//   "batches" the batch list changed (a status or a count of runs per status)
// Reads only; one read-only connection per poll, so it never blocks the writer.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <thread>

#include "server/http/event_hub.h"

namespace dash::log {
class ResultsDb;
}

namespace dash::http {

class DbWatcher {
 public:
  DbWatcher(std::string db_path, EventHub& hub, double period_seconds);
  ~DbWatcher();  ///< stop()
  DbWatcher(const DbWatcher&) = delete;
  DbWatcher& operator=(const DbWatcher&) = delete;

  void stop();

 private:
  void loop();
  void poll(const log::ResultsDb& db);

  std::string db_path_;
  EventHub& hub_;
  double period_;
  std::int64_t last_id_ = -1;                   ///< highest run id seen (-1: not yet read)
  std::map<std::string, std::string> watched_;  ///< uuid -> status, for runs seen running
  std::map<std::string, std::string> sizes_;    ///< uuid -> last published sizes message
  std::string batches_fingerprint_;
  bool have_fingerprint_ = false;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace dash::http
