#pragma once
// BatchRunner: runs a batch's runs, each in its own process, and records them in a results
// database. One code path for `dashbench batch run|resume` and the server.
//
// Each run is a child process (fork + exec of the dashbench binary, subcommand run-one), so a
// crash, a hang or running out of memory in one run never takes down the batch or its host:
//   - time: the planner gets the time limit as its deadline; from outside, the runner sends
//     SIGTERM at the limit (+5% + slack) and SIGKILL after a grace period. Recorded as 'timeout'.
//   - memory: RLIMIT_AS of the child is set before exec. An allocation failure is 'crashed'.
//   - crash: a child ended by a signal is 'crashed' with its exit signal and stderr's last lines.
// Only the runner writes the database: children stream events and their result through a pipe
// (run_protocol.h) into the SqliteRecorder of their run.
//
// Threads: start()/resume() prepare the batch synchronously (errors throw there), then one runner
// thread spawns children, reads their pipes (poll), writes the database and calls the progress
// callback. cancel() may be called from any thread and from a signal handler. wait() joins.
// The host process must leave SIGCHLD at its default (not SIG_IGN) and must not reap children it
// did not start (waitpid(-1, ...)): the runner thread reaps its own children by pid. Several
// BatchRunners may run at once in one process (each its own thread and database connection).
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "engine/log/results_db.h"
#include "server/batch/batch_spec.h"

namespace dash::batch {

struct RunnerOptions {
  int workers = 1;               ///< runs at once
  std::string executable;        ///< the dashbench binary to exec; empty: /proc/self/exe
  std::string batch_id;          ///< start(): the new batch's id; empty: "<name>-<UTC time>-<random>"
  double kill_grace = 2.0;       ///< seconds between SIGTERM and SIGKILL
  double time_slack = 0.5;       ///< seconds past the time limit (+5%) before SIGTERM
  double setup_allowance = 120;  ///< seconds a child may spend generating its scene before its
                                 ///< planner's clock starts (counted on top of the time limit)
  bool force_resume = false;     ///< resume even when a live runner's heartbeat is fresh
};

/// A run that just ended (in the progress callback).
struct FinishedRun {
  std::string key;
  std::string uuid;
  log::RunStatus status = log::RunStatus::Solved;
  double seconds = 0.0;  ///< wall time of the child process
  std::string error;
  int exit_signal = 0;
};

/// A run in progress (in the progress callback).
struct ActiveRun {
  std::string key;
  std::string uuid;
  double seconds = 0.0;  ///< since its process started
  /// The latest progress a long phase of its planner reported (conflict resolution: steps scheduled
  /// of the plan's, the step's robots, steps per second); none before the first.
  std::optional<log::ProgressEvent> work;
  /// The phase its planner is in now (paper's phases, log::Phase); none before the first phase starts.
  std::optional<log::Phase> phase;
};

struct BatchProgress {
  std::string batch_id;
  std::string name;
  std::int64_t total = 0;    ///< runs in the batch
  std::int64_t skipped = 0;  ///< complete before this runner started (resume)
  std::int64_t done = 0;     ///< with a final result, skipped ones included
  std::int64_t solved = 0;
  std::int64_t failed = 0;  ///< done but not solved: timeout + infeasible + crashed
  std::int64_t timeouts = 0;
  std::int64_t crashed = 0;
  std::int64_t cancelled = 0;  ///< stopped by cancel() (re-run by a later resume)
  std::int64_t axis_skipped = 0;  ///< not run: the axis stop rule skipped them (counted in done)
  std::int64_t running = 0;
  std::int64_t remaining = 0;  ///< total - done
  double elapsed = 0.0;        ///< seconds since this runner started
  double eta = -1.0;           ///< seconds; < 0 while unknown
  bool cancelling = false;
  std::optional<FinishedRun> finished;  ///< set when the callback reports a run that just ended
  std::vector<ActiveRun> active;        ///< the runs running now, oldest first
};

using ProgressCallback = std::function<void(const BatchProgress&)>;

struct BatchResult {
  std::string batch_id;
  std::string status;  ///< "finished", "cancelled", or "interrupted" (the runner itself failed)
  BatchProgress progress;
  std::string error;  ///< why the runner failed, for "interrupted"
};

class BatchRunner {
 public:
  BatchRunner();
  ~BatchRunner();  ///< a batch still running is cancelled and waited for
  BatchRunner(const BatchRunner&) = delete;
  BatchRunner& operator=(const BatchRunner&) = delete;

  /// Records a new batch (status 'queued', its spec and expanded run list) in `db_path` (created if
  /// missing), then runs it in the background. Returns the batch id. Throws InputError (bad path,
  /// duplicate id) before anything runs. One batch per BatchRunner.
  std::string start(const BatchSpec& spec, const std::string& db_path, const RunnerOptions& options,
                    ProgressCallback progress = {});
  /// Runs what batch `batch_id` of `db_path` is missing: runs never started, cancelled, or left
  /// 'running' by a runner that died (their row and partial events are replaced; a key never has two
  /// rows). Throws InputError for an unknown batch, or one whose runner is still alive.
  std::string resume(const std::string& batch_id, const std::string& db_path, const RunnerOptions& options,
                     ProgressCallback progress = {});

  /// Stops the batch: no new runs start; running children get SIGTERM (their planners stop via the
  /// deadline's stop flag) and SIGKILL after the grace period; they are recorded 'cancelled'. A
  /// second call kills the children at once. Async-signal-safe; no-op when nothing runs.
  void cancel() noexcept;
  /// Blocks until the batch ends; returns its outcome. Call once per start()/resume().
  BatchResult wait();
  /// True once the runner thread has ended (wait() will not block).
  bool done() const;
  /// A snapshot of the progress (any thread).
  BatchProgress progress() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// A new batch id: "<name>-<yyyymmdd-hhmmss>-<4 hex>" (name reduced to [A-Za-z0-9_-]).
std::string newBatchId(const std::string& name);

}  // namespace dash::batch
