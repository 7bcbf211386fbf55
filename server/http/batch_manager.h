#pragma once
// BatchManager: the server's launch queue. Batches submitted through the API are recorded in the
// results database at once (status 'queued', with their expanded run list), then run by
// server/batch's BatchRunner when a slot is free: each run in its own process, the runner's loop on
// the runner's own thread, never on an HTTP worker. Progress goes to the EventHub as "batch" events.
//
// Because a queued batch is stored before it runs, nothing is lost when the server stops: a batch
// that was queued or running in a server that is gone shows as 'interrupted' and resumes like any
// other (BatchRunner::resume runs exactly what is missing).
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "server/batch/batch_runner.h"
#include "server/http/event_hub.h"

namespace dash::http {

struct BatchManagerOptions {
  std::string db_path;
  std::string executable;       ///< the dashbench binary that runs each run; empty: /proc/self/exe
  int max_running = 1;          ///< batches run at once; later ones wait 'queued'
  int max_workers = 4;          ///< the most runs at once a request may ask for
  std::size_t max_runs = 5000;  ///< a spec that expands to more runs is refused
};

/// A batch for the Slurm backend (server/batch/slurm_backend.h): sbatch's options.
struct SlurmRequest {
  std::string partition;
  std::string account;
  int max_parallel = 0;  ///< array tasks at once; 0: no limit
};

struct SubmitOutcome {
  std::string batch_id;
  std::size_t runs = 0;
  std::string status;  ///< "queued" (it starts as soon as a slot is free)
};

class BatchManager {
 public:
  BatchManager(BatchManagerOptions options, EventHub& hub);
  ~BatchManager();  ///< shutdown()
  BatchManager(const BatchManager&) = delete;
  BatchManager& operator=(const BatchManager&) = delete;

  const BatchManagerOptions& options() const { return options_; }

  /// Validates a spec (the same JSON as `dashbench batch run`): {"runs", "keys" (the first
  /// `max_keys`), "name"}. Throws SpecError (an InputError) naming the field.
  std::string validateJson(const std::string& spec_json, std::size_t max_keys) const;
  /// Validates, records and queues a batch. Throws SpecError / HttpError 400 (bad workers).
  SubmitOutcome submit(const std::string& spec_json, int workers);
  /// Whether the Slurm backend is offered: sbatch is on the server's PATH.
  bool slurmAvailable() const;
  /// Validates, records and submits a batch as a Slurm job array (status 'submitted'); the loop then
  /// follows it and merges its shards. Throws SpecError, HttpError 400 (Slurm unavailable), or
  /// InputError with sbatch's message.
  SubmitOutcome submitSlurm(const std::string& spec_json, const SlurmRequest& request);

  /// Cancels a queued or running batch of this server (a Slurm batch: scancel). HttpError 404 (unknown), 409 (not running here).
  void cancel(const std::string& batch_id);
  /// Queues the missing runs of an interrupted or cancelled batch. HttpError 404, 409 (running, or
  /// nothing is missing).
  void resume(const std::string& batch_id, int workers);

  /// {"batches": [...]}: every batch of the database, newest first, with this server's live state.
  std::string batchesJson() const;
  /// One batch with its spec and its stored runs; HttpError 404 if unknown.
  std::string batchJson(const std::string& batch_id) const;

  /// Cancels the running batches (their runs are recorded 'cancelled') and waits for them.
  void shutdown();

 private:
  struct Active {
    std::unique_ptr<batch::BatchRunner> runner;  ///< null while starting
    int workers = 1;
    std::optional<batch::BatchProgress> progress;
    bool cancel_requested = false;
  };
  struct Queued {
    std::string batch_id;
    int workers = 1;
  };

  void loop();
  /// Brings the Slurm batches still in Slurm up to date (states, shards merged); on the loop's thread.
  void pollSlurm();
  void startQueued(const Queued& q);
  void onProgress(const batch::BatchProgress& p);
  void publishBatch(const std::string& batch_id) const;
  int checkedWorkers(int workers) const;
  batch::SpecOptions specOptions() const;

  BatchManagerOptions options_;
  EventHub& hub_;
  mutable std::mutex mutex_;
  std::mutex submit_mutex_;  ///< one submit writes to the database at a time
  std::condition_variable cv_;
  std::map<std::string, Active> active_;
  std::deque<Queued> queue_;
  bool stopping_ = false;
  std::chrono::steady_clock::time_point last_slurm_poll_{};
  std::thread thread_;
};

}  // namespace dash::http
