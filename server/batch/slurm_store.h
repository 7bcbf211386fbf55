#pragma once
// The Slurm backend's own tables in the results database, next to the batch runner's (batch_store.h):
//
//   dash_slurm_jobs  (batch_id, submission) -> job_id, shard_dir, tasks, submitted, cancelled,
//                    options (JSON: partition, account, max_parallel, runs_per_task, executable).
//                    Submission 1 is `batch run`; each `batch resume` adds one.
//   dash_slurm_tasks (batch_id, submission, task) -> state (the last Slurm state seen, slurm_client.h
//                    names), source (squeue, sacct or shard), shard_stamp (size and mtime of the
//                    shard when it was last merged; a shard is merged again only once it changed).
//   dash_slurm_runs  (batch_id, submission, run_key) -> task: which array task ran the key.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/log/results_db.h"

namespace dash::batch {

struct SlurmJobRecord {
  std::string batch_id;
  int submission = 1;
  std::string job_id;
  std::string shard_dir;
  int tasks = 0;
  std::string submitted;  ///< ISO 8601, UTC
  bool cancelled = false;
  std::string options_json = "{}";
};

struct SlurmTaskRecord {
  int task = 0;
  std::string state = "pending";
  std::string source;
  std::string shard_stamp;
};

class SlurmStore {
 public:
  /// Opens `path`, which must hold a results database (open a ResultsDb first). Read-write mode
  /// creates the tables if missing; read-only mode reads them if present.
  explicit SlurmStore(const std::string& path, log::OpenMode mode = log::OpenMode::ReadWrite);
  ~SlurmStore();
  SlurmStore(const SlurmStore&) = delete;
  SlurmStore& operator=(const SlurmStore&) = delete;

  /// Records a submission, its tasks (state 'pending') and which task runs which key.
  void addJob(const SlurmJobRecord& job, const std::vector<std::vector<std::string>>& task_keys);
  /// Every submission of the batch, oldest first (empty: not a Slurm batch).
  std::vector<SlurmJobRecord> jobs(const std::string& batch_id) const;
  /// The batches that have a submission.
  std::vector<std::string> batchIds() const;
  void setCancelled(const std::string& batch_id, int submission);

  std::vector<SlurmTaskRecord> tasks(const std::string& batch_id, int submission) const;
  void setTaskState(const std::string& batch_id, int submission, int task, const std::string& state,
                    const std::string& source);
  void setShardStamp(const std::string& batch_id, int submission, int task, const std::string& stamp);
  /// run key -> task of one submission.
  std::map<std::string, int> runTasks(const std::string& batch_id, int submission) const;

 private:
  struct Impl;
  Impl* impl_;
};

}  // namespace dash::batch
