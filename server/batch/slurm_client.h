#pragma once
// Slurm's command-line tools, as the batch backend uses them: sbatch to submit, squeue (and sacct,
// where the cluster keeps accounting) to see the array tasks' states, scancel to cancel. The
// commands are found on the PATH and configured the usual way (SLURM_CONF, /etc/slurm).
// Parsing is separate from running, so that it is tested without a cluster.
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace dash::batch {

/// An array task's state, reduced to what the workbench shows.
enum class SlurmState { kPending, kRunning, kCompleted, kFailed, kTimeout, kCancelled, kUnknown };
const char* toString(SlurmState state);
/// Slurm's state names (squeue %T, sacct State): PENDING, RUNNING, COMPLETING, COMPLETED, FAILED,
/// TIMEOUT, CANCELLED (also "CANCELLED by 0"), OUT_OF_MEMORY, NODE_FAIL, PREEMPTED, ...
SlurmState parseSlurmState(const std::string& text);
/// "pending", ... as toString writes them; kUnknown for anything else.
SlurmState slurmStateFromName(const std::string& name);
/// Whether the task has ended (its shard will not change any more).
bool isFinal(SlurmState state);

/// The job id in sbatch --parsable output ("1234" or "1234;cluster"); InputError if none.
std::string parseSbatchJobId(const std::string& output);
/// Lines "JOBID_TASK|STATE" (squeue -h -r -o '%i|%T', or sacct -n -P -X -o JobID,State) of job
/// `job_id`: task index -> state. Lines of other jobs, job steps ("1234_5.batch") and unexpanded
/// ranges ("1234_[3-9%2]") are skipped.
std::map<int, SlurmState> parseArrayStates(const std::string& output, const std::string& job_id);

struct CommandResult {
  int exit_code = -1;  ///< -1: could not start (err says why), 128+N: killed by signal N
  std::string out;
  std::string err;
};

/// Runs `argv` (argv[0] looked up on the PATH) with stdin on /dev/null and returns its output and
/// exit code; kills it after `timeout_seconds`. Reaps only its own child (safe inside the server).
CommandResult runCommand(const std::vector<std::string>& argv, double timeout_seconds = 60.0);
/// Whether `name` is an executable file in a directory of the PATH.
bool onPath(const std::string& name);

class SlurmClient {
 public:
  /// Whether sbatch is on the PATH (the Slurm backend is offered only then).
  static bool available();

  /// sbatch --parsable [extra...] SCRIPT; returns the job id. InputError with sbatch's message if refused.
  std::string submit(const std::string& script_path, const std::vector<std::string>& extra_args = {}) const;
  /// The states of the job's array tasks the controller still knows (squeue -t all: ended tasks stay
  /// for the cluster's MinJobAge). nullopt when squeue fails (controller unreachable).
  std::optional<std::map<int, SlurmState>> queue(const std::string& job_id) const;
  /// The same from sacct; nullopt when sacct fails or the cluster keeps no accounting.
  std::optional<std::map<int, SlurmState>> accounting(const std::string& job_id) const;
  /// scancel JOB_ID; InputError with scancel's message if it fails.
  void cancel(const std::string& job_id) const;
};

}  // namespace dash::batch
