#pragma once
// DispatchRecorder: writes every dispatch to the results database (log::DispatchStore) as the
// service reports it: when the arms start, when it ends (per arm: result, deviation, samples; the
// abort reason), and requests refused before anything moved. Also the history's JSON for the API.
//
// A database failure never stops a dispatch: the recorder keeps the error (lastError()) and says it
// on stderr, and the arms carry on.
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "engine/log/dispatch_store.h"
#include "server/dispatch/dispatch_listener.h"

namespace dash::dispatch {

class DispatchRecorder : public DispatchListener {
 public:
  /// Opens (creates, migrates) the results database at `db_path`.
  explicit DispatchRecorder(const std::string& db_path);

  void onPreflight(const PreflightReport& report, const std::string& dispatch_id) override;
  void onDispatchRefused(const DispatchStatus& record, const PreflightReport& report) override;
  void onDispatchStarted(const DispatchStatus& status) override;
  void onDispatchFinished(const DispatchStatus& status) override;

  /// {"dispatches": [record...], "total"}: newest first. A record: {"id", "created", "started",
  /// "ended", "state", "reason", "run_id", "scene", "planner", "requested_by", "client", "execution",
  /// "time_scale", "duration", "elapsed", "preflight": {...} | null, "arms": [{"robot", "driver", "status",
  /// "result": {"code", "name", "message"}, "duration", "max_deviation", "samples", "segments": [{"node",
  /// "kind", "planned": [start, end], "executed": [start, end]}] | null}]}. "duration" is the planned
  /// makespan (scaled), "elapsed" the executed one.
  std::string historyJson(int limit, int offset) const;
  /// One record's JSON; empty if there is no such dispatch.
  std::string recordJson(const std::string& id) const;
  std::string lastError() const;

  /// The record a status becomes (times turned from the steady clock into UTC text).
  static log::DispatchRecord toRecord(const DispatchStatus& status, const std::string& preflight_json);

 private:
  void save(const log::DispatchRecord& record);

  log::DispatchStore store_;
  mutable std::mutex mutex_;
  std::map<std::string, std::string> preflight_;  ///< dispatch id -> report JSON, until it is final
  std::string last_error_;
};

}  // namespace dash::dispatch
