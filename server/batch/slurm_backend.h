#pragma once
// SlurmBackend: a batch run as a Slurm job array instead of by a local runner.
//
//   submit : records the batch in the results database (as `batch run` does: status, spec,
//            expanded run list), writes the manifest and the job script into the shard directory
//            (on storage shared with the compute nodes), and submits it with sbatch
//            (--array=0-(N-1)%max_parallel). Each array task is a SlurmTask (slurm_task.h).
//   update : asks Slurm for the tasks' states (squeue, then sacct, then the task's own state file:
//            a cluster without accounting forgets ended jobs after MinJobAge), and merges every
//            shard that changed since its last merge into the results database (ResultsDb::mergeFrom,
//            the code of `dashbench db merge`). A key never gets two runs: a shard's run is adopted
//            only when the key has no final result yet; any other copy (a requeued task's, an old
//            submission's) is dropped again (BatchStore::deleteOrphans). Sets the batch's status:
//            'submitted' while tasks are pending or running, then 'finished' (every run has a final
//            result), 'cancelled' (cancel() was called) or 'interrupted' (tasks failed or ran out
//            of time: resume runs what is missing).
//   cancel : scancel for the batch's submissions that still have tasks in Slurm.
//   resume : a new submission with exactly the runs that have no final result.
//
// Only one process should update a batch at a time (the database has one writer); `batch run`
// follows its batch until it ends, `batch status` updates it on demand, and the server polls.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "server/batch/batch_spec.h"
#include "server/batch/slurm_client.h"

namespace dash::batch {

struct SlurmSubmitOptions {
  std::string partition;   ///< --partition; empty: the cluster's default
  std::string account;     ///< --account; empty: the user's default
  int max_parallel = 0;    ///< array tasks at once (%N); 0: no limit of ours
  int runs_per_task = 1;   ///< runs per array task (raised to keep the array within kMaxArrayTasks)
  std::string shard_dir;   ///< empty: DB.slurm/BATCH_ID next to the database (must be shared)
  std::string executable;  ///< the dashbench binary on the nodes; empty: this one
  std::string batch_id;    ///< submit(): empty: newBatchId(name)
};

/// One array task as update() saw it.
struct SlurmTaskView {
  int submission = 1;
  std::string job_id;
  int task = 0;
  SlurmState state = SlurmState::kPending;
  std::string source;  ///< "squeue", "sacct", "shard" (its state file), or "" (not seen yet)
  std::vector<std::string> keys;
};

struct SlurmBatchView {
  std::string batch_id;
  std::string status;  ///< the batch's status after the update
  std::vector<SlurmTaskView> tasks;
  std::map<SlurmState, int> by_state;
  std::int64_t runs = 0;     ///< in the batch's run list
  std::int64_t complete = 0; ///< runs with a final result in the results database
  std::map<std::string, std::string> run_status;  ///< key -> its run's status ("" if none yet)
  std::int64_t merged = 0;   ///< runs adopted by this update
  bool active = false;       ///< some task is pending or running (or Slurm could not be asked)
};

class SlurmBackend {
 public:
  explicit SlurmBackend(std::string db_path, SlurmClient client = {});

  /// Submits `spec`; returns the batch id. InputError (bad options, sbatch refused: its message); then
  /// nothing of the batch is recorded.
  std::string submit(const BatchSpec& spec, const SlurmSubmitOptions& options);
  /// Submits the batch's runs without a final result; returns how many. Options left empty take
  /// the last submission's. InputError if tasks are still in Slurm or nothing is missing.
  std::int64_t resume(const std::string& batch_id, const SlurmSubmitOptions& options = {});
  /// Queries Slurm and merges the shards that changed.
  SlurmBatchView update(const std::string& batch_id);
  /// scancel; the runs then record 'cancelled' (merged by the next updates).
  void cancel(const std::string& batch_id);

  /// Whether the batch was submitted to Slurm (read-only; false for a database without the tables).
  static bool isSlurmBatch(const std::string& db_path, const std::string& batch_id);

 private:
  std::string submitRuns(const std::string& batch_id, const std::string& name, const std::vector<RunSpec>& runs,
                         double time_limit, double memory_limit_mb, const SlurmSubmitOptions& options, int submission,
                         const BatchSpec* new_batch = nullptr);

  std::string db_path_;
  SlurmClient client_;
};

/// `dashbench batch status` for a Slurm batch: the tasks per Slurm state, then (with `per_run`)
/// one line per array task with its state and its runs' statuses.
std::string formatSlurmView(const SlurmBatchView& view, bool per_run);

}  // namespace dash::batch
