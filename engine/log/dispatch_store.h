#pragma once
// The dispatch history in the results database (schema version 3: dash_dispatches and one
// dash_dispatch_arms row per arm; version 8: how it ran and each step's times). The server's dispatch
// service writes a record when a dispatch starts and again when it ends (or when a request is refused before anything moved); the dashboard
// reads it back. Plain strings and numbers only: the dispatch vocabulary stays in server/dispatch.
//
// Uses its own SQLite connection (busy timeout), guarded by a mutex: any thread may call it.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/log/results_db.h"

namespace dash::log {

struct DispatchArmRecord {
  std::string robot;
  std::string driver;        ///< "sim", "ur", ...
  std::string status;        ///< the arm's last status: idle, armed, executing, succeeded, failed, aborted
  std::string result;        ///< SUCCESSFUL, PATH_TOLERANCE_VIOLATED, CANCELLED, FAULT, ... ("" = not started)
  int result_code = 0;       ///< FollowJointTrajectory's error code (and the two of server/dispatch)
  std::string message;
  double duration = 0.0;       ///< s: when its goal ends
  double max_deviation = 0.0;  ///< rad (m): measured against planned
  int samples = 0;             ///< joint states received
  /// Execution by dependencies: [{"node", "kind", "planned": [start, end], "executed": [start, end]}]
  /// as JSON text (s from the start; executed null where it never ran); empty for a timed dispatch.
  std::string segments;
};

struct DispatchRecord {
  std::string id;
  std::string created;  ///< ISO 8601 UTC: when the request arrived
  std::string started;  ///< the common start time; empty if the arms were never started
  std::string ended;    ///< empty while active
  std::string state;    ///< arming, running, succeeded, failed, aborted, refused
  std::string reason;   ///< why it ended: the abort or refusal reason (empty on success)
  std::string run_uuid;      ///< the stored run whose plan it was; empty for a plan sent with the request
  std::string scene;
  std::string planner;
  std::string requested_by;  ///< the user label of the request, else "token holder"
  std::string client;        ///< the requesting client's address
  double time_scale = 1.0;
  std::string execution = "timed";  ///< "timed" (one common start) or "tpg" (by dependencies)
  double duration = 0.0;  ///< s: the latest arm end time
  double elapsed = 0.0;   ///< s from the start time to the end (0 if never started)
  std::string preflight;  ///< the pre-flight report as JSON text ("" if none)
  std::vector<DispatchArmRecord> arms;
};

/// "2026-11-21T13:21:05.123Z" for milliseconds since the Unix epoch.
std::string isoTimeFromUnixMillis(std::int64_t unix_ms);

class DispatchStore {
 public:
  /// Opens `path`. ReadWrite creates and migrates the file if needed (as ResultsDb does); ReadOnly
  /// requires the current schema.
  explicit DispatchStore(const std::string& path, OpenMode mode = OpenMode::ReadWrite);
  ~DispatchStore();
  DispatchStore(const DispatchStore&) = delete;
  DispatchStore& operator=(const DispatchStore&) = delete;

  /// Inserts the record or replaces the one with its id (arms included), in one transaction.
  void save(const DispatchRecord& record);
  /// Newest first (by creation time, then id).
  std::vector<DispatchRecord> list(int limit = 50, int offset = 0) const;
  std::optional<DispatchRecord> get(const std::string& id) const;
  std::int64_t count() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dash::log
