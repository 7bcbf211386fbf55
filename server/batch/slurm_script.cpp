#include "server/batch/slurm_script.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "engine/core/check.h"

namespace dash::batch {
namespace {

constexpr double kRunTimeMargin = 1.25;    ///< the runner stops a run at limit * 1.05 + slack; room above
constexpr double kRunSetupSeconds = 60.0;  ///< scene generation and process start, per run
constexpr double kTaskSeconds = 60.0;      ///< the task process: reading the manifest, copying the shard
constexpr double kMemMargin = 1.10;
constexpr int kTaskMemMb = 512;

/// Slurm reads #SBATCH values up to the end of the line: a newline would smuggle in another option.
void requireOneLine(const std::string& value, const char* what) {
  DASH_THROW_UNLESS(value.find_first_of("\r\n") == std::string::npos, std::string(what) + ": must be one line");
}

}  // namespace

SlurmResources taskResources(double time_limit, double memory_limit_mb, int runs_per_task) {
  DASH_THROW_UNLESS(time_limit > 0, "time_limit must be positive");
  DASH_THROW_UNLESS(memory_limit_mb >= 0, "memory_limit must not be negative");
  DASH_THROW_UNLESS(runs_per_task >= 1, "runs per task must be at least 1");
  SlurmResources r;
  const double seconds = runs_per_task * (time_limit * kRunTimeMargin + kRunSetupSeconds) + kTaskSeconds;
  r.time_minutes = static_cast<int>(std::ceil(seconds / 60.0));
  if (memory_limit_mb > 0) r.mem_mb = static_cast<int>(std::ceil(memory_limit_mb * kMemMargin)) + kTaskMemMb;
  return r;
}

std::string formatSlurmTime(int minutes) {
  DASH_THROW_UNLESS(minutes >= 1, "a Slurm time limit is at least one minute");
  const int days = minutes / (24 * 60);
  const int hours = minutes / 60 % 24;
  const int mins = minutes % 60;
  char buf[48];
  if (days > 0) {
    std::snprintf(buf, sizeof buf, "%d-%02d:%02d:00", days, hours, mins);
  } else {
    std::snprintf(buf, sizeof buf, "%d:%02d:00", hours, mins);
  }
  return buf;
}

int runsPerTask(std::size_t runs, int requested) {
  DASH_THROW_UNLESS(requested >= 1, "--runs-per-task must be at least 1");
  const auto needed = static_cast<int>((runs + kMaxArrayTasks - 1) / kMaxArrayTasks);
  return std::max(requested, std::max(needed, 1));
}

std::vector<std::vector<int>> chunkRuns(std::size_t runs, int runs_per_task) {
  DASH_THROW_UNLESS(runs_per_task >= 1, "runs per task must be at least 1");
  std::vector<std::vector<int>> tasks;
  for (std::size_t i = 0; i < runs; ++i) {
    if (i % static_cast<std::size_t>(runs_per_task) == 0) tasks.emplace_back();
    tasks.back().push_back(static_cast<int>(i));
  }
  return tasks;
}

std::string shellQuote(const std::string& text) {
  std::string out = "'";
  for (char c : text) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

std::string formatJobScript(const JobScript& job) {
  DASH_THROW_UNLESS(job.tasks >= 1, "a job array needs at least one task");
  DASH_THROW_UNLESS(job.max_parallel >= 0, "--max-parallel must not be negative");
  DASH_THROW_UNLESS(!job.executable.empty() && job.executable.front() == '/', "the executable must be an absolute path");
  requireOneLine(job.job_name, "job name");
  requireOneLine(job.partition, "--partition");
  requireOneLine(job.account, "--account");
  requireOneLine(job.log_dir, "the shard directory");
  DASH_THROW_UNLESS(job.partition.find_first_of(" \t") == std::string::npos, "--partition: no spaces");
  DASH_THROW_UNLESS(job.account.find_first_of(" \t") == std::string::npos, "--account: no spaces");
  std::ostringstream s;
  s << "#!/bin/bash\n";
  s << "# A dashbench batch as a Slurm job array: each array task runs its runs, each in its own\n";
  s << "# process, into its own SQLite shard; `dashbench batch status` merges the shards.\n";
  s << "#SBATCH --job-name=" << job.job_name << "\n";
  s << "#SBATCH --array=0-" << job.tasks - 1;
  if (job.max_parallel > 0) s << "%" << job.max_parallel;
  s << "\n";
  s << "#SBATCH --ntasks=1\n";
  s << "#SBATCH --cpus-per-task=" << job.resources.cpus << "\n";
  s << "#SBATCH --time=" << formatSlurmTime(job.resources.time_minutes) << "\n";
  if (job.resources.mem_mb > 0) s << "#SBATCH --mem=" << job.resources.mem_mb << "M\n";
  if (!job.partition.empty()) s << "#SBATCH --partition=" << job.partition << "\n";
  if (!job.account.empty()) s << "#SBATCH --account=" << job.account << "\n";
  // An #SBATCH value is not a shell word (a path with spaces would be cut): the submitter passes
  // --output on sbatch's command line as well, which wins; this line is for resubmitting by hand.
  s << "#SBATCH --output=" << job.log_dir << "/slurm-%A_%a.out\n";
  s << "exec " << shellQuote(job.executable) << " batch slurm-task --manifest " << shellQuote(job.manifest)
    << " --task \"$SLURM_ARRAY_TASK_ID\"\n";
  return s.str();
}

}  // namespace dash::batch
