#pragma once
// The batch runner's own tables in the results database (created on first use, next to the
// results schema of engine/log; `dash_batches` itself belongs to engine/log):
//
//   dash_batch_runs   (batch_id, run_key) -> ordinal, the run's description (RunSpec JSON),
//                     run_uuid (the dash_runs row of the key's current attempt; NULL before its
//                     first start), attempts. Written when a batch starts: the expanded run list
//                     with stable keys, which is what `batch resume` runs from.
//   dash_batch_skipped (batch_id, run_key) -> reason: runs the axis stop rule (axis_stop.h) skipped;
//                     they have no dash_runs row and count as complete.
//   dash_batch_runner (batch_id) -> pid, host, started, heartbeat (unix seconds), workers: the
//                     process running the batch; a heartbeat older than kStaleHeartbeatSeconds
//                     means that process is gone (the batch shows as 'interrupted').
//
// A key has at most one dash_runs row: a new attempt first deletes the previous attempt's row
// (and its events), then records the new uuid, then begins the run.
//
// The store uses its own SQLite connection. Its writes must not overlap a write transaction of a
// ResultsDb in the same thread: call ResultsDb::flush() first (the runner does).
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/log/results_db.h"
#include "server/batch/batch_spec.h"

namespace dash::batch {

inline constexpr double kStaleHeartbeatSeconds = 15.0;

/// One run of a stored batch, with the state of its dash_runs row (if any).
struct StoredRun {
  RunSpec spec;
  std::string run_uuid;  ///< empty: never started
  int attempts = 0;
  std::optional<std::string> status;  ///< the dash_runs row's status; nullopt: no row
  std::string error;
  std::string skipped;  ///< why the axis stop rule skipped it; empty: not skipped

  /// True when the run has a final result that resume keeps: solved, timeout, infeasible, or
  /// crashed (unless the crash is a runner's death closed by markInterrupted: "interrupted: ..."),
  /// or it was skipped by the axis stop rule.
  bool complete() const;
};

struct RunnerInfo {
  std::int64_t pid = 0;
  std::string host;
  std::string started;
  double heartbeat = 0.0;  ///< unix seconds
  int workers = 0;
  /// Seconds since the last heartbeat.
  double age() const;
  /// Whether the runner process still exists: on this host, by its pid; elsewhere, by a fresh heartbeat.
  bool alive() const;
};

class BatchStore {
 public:
  /// Opens `path`, which must already hold a results database (open a ResultsDb first: it creates
  /// and migrates). Read-write mode creates the batch tables if missing.
  explicit BatchStore(const std::string& path, log::OpenMode mode = log::OpenMode::ReadWrite);
  ~BatchStore();
  BatchStore(const BatchStore&) = delete;
  BatchStore& operator=(const BatchStore&) = delete;

  /// Stores the expanded run list of a new batch (one transaction). Throws InputError if the
  /// batch already has runs stored.
  void addRuns(const std::string& batch_id, const std::vector<RunSpec>& runs);
  /// Every stored run of the batch, in ordinal order, joined with its dash_runs row.
  std::vector<StoredRun> runs(const std::string& batch_id) const;
  std::int64_t runCount(const std::string& batch_id) const;
  /// The batch's stored runs counted in one query, without reading their descriptions (a list of
  /// batches with 200,000 stored runs took 3-7 s when it read them all).
  struct Counts {
    std::int64_t total = 0;
    std::int64_t pending = 0;  ///< runs not StoredRun::complete()
    std::int64_t skipped = 0;
  };
  Counts counts(const std::string& batch_id) const;

  /// Records `uuid` as the key's current attempt (attempts + 1).
  void assignUuid(const std::string& batch_id, const std::string& key, const std::string& uuid);
  /// Deletes a dash_runs row and its rows in every table keyed by run_id (events, constraints,
  /// phases, ...). No-op for an unknown uuid.
  void deleteRun(const std::string& uuid);
  /// Deletes the batch's dash_runs rows that no key refers to (left by a runner killed between
  /// steps). Returns how many.
  int deleteOrphans(const std::string& batch_id);

  /// Records that the axis stop rule skipped the run (its dash_runs row, if any, is deleted first).
  void markSkipped(const std::string& batch_id, const std::string& key, const std::string& reason);

  /// Sets dash_runs.scene of a run (the name is known once its process generated the scene).
  void setScene(const std::string& uuid, const std::string& scene);

  void setRunner(const std::string& batch_id, const RunnerInfo& info);
  void heartbeat(const std::string& batch_id);
  void clearRunner(const std::string& batch_id);
  std::optional<RunnerInfo> runner(const std::string& batch_id) const;

 private:
  struct Impl;
  Impl* impl_;
};

/// A batch as `dashbench batch status` and the server show it.
struct BatchInfo {
  log::BatchRecord record;
  /// record.status, except 'running' whose runner is gone (RunnerInfo::alive): 'interrupted'.
  std::string status;
  std::int64_t total = 0;                         ///< runs in the stored run list (0 if none was stored)
  std::map<std::string, std::int64_t> by_status;  ///< dash_runs rows of the batch per status, and "skipped"
  std::int64_t pending = 0;                       ///< keys without a final result (never started, or to re-run)
  std::optional<RunnerInfo> runner;
};

/// Every batch of the file (read-only), or just `batch_id` (InputError if unknown).
std::vector<BatchInfo> listBatchInfo(const std::string& db_path, const std::string& batch_id = "");
/// A table for people: one line per batch with its counts per run status.
std::string formatBatchInfo(const std::vector<BatchInfo>& batches);

}  // namespace dash::batch
