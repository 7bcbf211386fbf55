#pragma once
// One Slurm array task of a batch (`dashbench batch slurm-task --manifest M --task N`, started by
// the job script). It runs its runs one after another through the local backend's runner
// (BatchRunner: each run in its own child process, with the batch's time and memory limits), each
// into a small SQLite file on the node's local disk, and merges each finished run into the task's
// shard. After every run the shard is published on shared storage as SHARD_DIR/task-N.db: copied
// to task-N.db.part in rollback-journal mode (SQLite's WAL must not be shared between hosts over a
// network file system), then renamed, so a reader never sees half a file.
//
// A requeued task (node failure, preemption, scontrol requeue) starts from its published shard and
// skips the runs it holds with a final result, so it never records a run twice; a run it holds
// unfinished or cancelled is replaced. The shard's table dash_slurm_shard_runs maps each run key to
// the run's uuid: the submitter reads it when merging (slurm_backend.h).
//
// When it ends the task writes SHARD_DIR/task-N.state: "completed" (every run ran) or "stopped"
// (it got SIGTERM/SIGINT: scancel, or Slurm's time limit), for clusters whose sacct has no data.
#include <atomic>
#include <string>
#include <vector>

#include "server/batch/batch_spec.h"

namespace dash::batch {

class BatchRunner;

/// What every array task of one submission reads: the manifest, written next to the shards.
struct SlurmManifest {
  std::string batch_id;
  std::string name;       ///< the batch's name
  int submission = 1;     ///< 1 for `batch run`, then one more per `batch resume`
  std::string shard_dir;  ///< where task-N.db and task-N.state go
  std::vector<std::vector<RunSpec>> tasks;  ///< the runs of each array task, in order
};

void writeManifest(const std::string& path, const SlurmManifest& manifest);
/// InputError naming the file if it cannot be read or parsed.
SlurmManifest readManifest(const std::string& path);

/// SHARD_DIR/task-N.db and SHARD_DIR/task-N.state.
std::string shardPath(const std::string& shard_dir, int task);
std::string taskStatePath(const std::string& shard_dir, int task);

/// The batch of one run: the same key, family, parameters, seed, planner and limits.
BatchSpec singleRunSpec(const RunSpec& run, const std::string& batch_name);

struct SlurmTaskOptions {
  std::string manifest;    ///< path of the submission's manifest
  int task = 0;            ///< SLURM_ARRAY_TASK_ID
  std::string executable;  ///< the dashbench binary the runner execs; empty: /proc/self/exe
  std::string work_dir;    ///< node-local scratch; empty: $TMPDIR or /tmp
};

class SlurmTask {
 public:
  explicit SlurmTask(SlurmTaskOptions options) : options_(std::move(options)) {}

  /// Runs the task's runs; returns the exit code: 0 every run ran, 130 stopped by cancel(), 2 bad
  /// input (unknown task index, unreadable manifest). Progress lines go to stderr (the task's log).
  int run();
  /// Stops after the current run, which is stopped too (recorded 'cancelled'). Async-signal-safe.
  void cancel() noexcept;

 private:
  SlurmTaskOptions options_;
  std::atomic<bool> cancelled_{false};
  std::atomic<BatchRunner*> runner_{nullptr};
};

}  // namespace dash::batch
