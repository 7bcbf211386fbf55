#pragma once
// The Slurm job array of a batch: which runs each array task gets, the resources each task asks
// for (from the batch's time and memory limits, with a margin), and the sbatch script itself.
// Pure functions: nothing here talks to Slurm (slurm_client.h does).
#include <string>
#include <vector>

namespace dash::batch {

/// Slurm's default MaxArraySize is 1001 (indices 0..1000): larger batches put several runs in a task.
inline constexpr int kMaxArrayTasks = 1000;

/// What one array task asks Slurm for.
struct SlurmResources {
  int time_minutes = 0;  ///< --time
  int mem_mb = 0;        ///< --mem; 0: not given (the partition's default)
  int cpus = 1;          ///< --cpus-per-task: a run is single-threaded
};

/// Resources of a task that runs `runs_per_task` runs one after another, each with the batch's
/// `time_limit` (seconds) and `memory_limit_mb` (0: none). Time: per run the limit plus the runner's
/// own margin (+25%, scene setup and process start: +60 s), plus a minute for the task itself,
/// rounded up to whole minutes. Memory: the run's address-space limit +10% plus 512 MB for the task
/// process and the runner (a run's resident memory stays below its address-space limit).
SlurmResources taskResources(double time_limit, double memory_limit_mb, int runs_per_task);

/// "H:MM:SS", or "D-HH:MM:SS" from a day on: Slurm's --time syntax.
std::string formatSlurmTime(int minutes);

/// Runs per array task: `requested` (>= 1), raised so that the array has at most kMaxArrayTasks tasks.
int runsPerTask(std::size_t runs, int requested);

/// The array task of each run (by position): run i goes to task i / runs_per_task.
std::vector<std::vector<int>> chunkRuns(std::size_t runs, int runs_per_task);

struct JobScript {
  std::string job_name;    ///< --job-name
  int tasks = 1;           ///< --array=0-(tasks-1)
  int max_parallel = 0;    ///< %N on the array; 0: Slurm's own limit
  SlurmResources resources;
  std::string partition;   ///< empty: the cluster's default
  std::string account;     ///< empty: the user's default
  std::string log_dir;     ///< each task's stdout/stderr: LOG_DIR/slurm-<job>_<task>.out
  std::string executable;  ///< the dashbench binary (an absolute path, the same on every node)
  std::string manifest;    ///< the submission's manifest (on shared storage)
};

/// The sbatch script: #SBATCH lines, then `exec dashbench batch slurm-task --manifest M --task
/// $SLURM_ARRAY_TASK_ID`. Values are shell-quoted; a value with a newline is an InputError.
std::string formatJobScript(const JobScript& job);

/// 'text' for a POSIX shell (single quotes, inner quotes escaped).
std::string shellQuote(const std::string& text);

}  // namespace dash::batch
