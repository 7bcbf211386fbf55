#include "server/batch/slurm_backend.h"

#include <sqlite3.h>

#include <algorithm>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"
#include "server/batch/batch_runner.h"
#include "server/batch/batch_store.h"
#include "server/batch/slurm_script.h"
#include "server/batch/slurm_store.h"
#include "server/batch/slurm_task.h"
#include "engine/core/host_info.h"

namespace dash::batch {

namespace fs = std::filesystem;
namespace sql = log::sql;
using Json = nlohmann::json;

namespace {

std::string readSmallFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in.good()) return "";
  std::string word;
  in >> word;
  return word;
}

/// Size and modification time: a published shard is replaced by rename, never written in place.
std::string shardStamp(const std::string& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  if (ec) return "";
  const auto mtime = fs::last_write_time(path, ec);
  if (ec) return "";
  return std::to_string(size) + ":" + std::to_string(mtime.time_since_epoch().count());
}

/// The state of a task Slurm no longer reports, from the state file the task wrote when it ended.
SlurmState stateFromTaskFile(const std::string& shard_dir, int task, bool cancelled_by_us) {
  const std::string word = readSmallFile(taskStatePath(shard_dir, task));
  if (word == "completed") return SlurmState::kCompleted;
  // A task stopped by a signal nobody asked for was, in all likelihood, stopped by its time limit.
  if (word == "stopped") return cancelled_by_us ? SlurmState::kCancelled : SlurmState::kTimeout;
  return cancelled_by_us ? SlurmState::kCancelled : SlurmState::kFailed;
}

bool isFinalRun(const std::string& status, const std::string& error) {
  if (status == "crashed") return error.rfind("interrupted:", 0) != 0;
  return status == "solved" || status == "timeout" || status == "infeasible";
}

/// key -> uuid of the shard's runs (the shard's own table, slurm_task.h).
std::vector<std::pair<std::string, std::string>> shardRuns(const std::string& shard) {
  std::vector<std::pair<std::string, std::string>> out;
  sql::Connection c = sql::open(shard, SQLITE_OPEN_READONLY);
  if (sql::selectInt(c.get(), "SELECT COUNT(*) FROM sqlite_master WHERE name = 'dash_slurm_shard_runs'") == 0)
    return out;
  sql::Statement st(c.get(), "SELECT run_key, run_uuid FROM dash_slurm_shard_runs");
  while (st.step()) out.emplace_back(st.columnText(0), st.columnText(1));
  return out;
}

/// After a shard was merged: each of its runs becomes its key's run unless the key already has a
/// final result (then the shard's copy is dropped). Returns how many final results were adopted.
std::int64_t adoptShardRuns(log::ResultsDb& db, BatchStore& store, const std::string& batch_id,
                            const std::string& shard) {
  std::map<std::string, StoredRun> stored;
  for (StoredRun& r : store.runs(batch_id)) stored.emplace(r.spec.key, std::move(r));
  std::int64_t adopted = 0;
  for (const auto& [key, uuid] : shardRuns(shard)) {
    const auto it = stored.find(key);
    if (it == stored.end()) continue;
    const StoredRun& current = it->second;
    if (current.run_uuid == uuid) continue;
    const log::SqlRows row = db.select("SELECT status, COALESCE(error, '') FROM dash_runs WHERE uuid = ?", {uuid});
    if (row.rows.empty()) continue;
    const bool final_result = isFinalRun(std::get<std::string>(row.rows[0][0]), std::get<std::string>(row.rows[0][1]));
    const bool take = !current.status.has_value() || (!current.complete() && final_result);
    if (!take) continue;
    if (!current.run_uuid.empty()) store.deleteRun(current.run_uuid);
    store.assignUuid(batch_id, key, uuid);
    if (final_result) ++adopted;
  }
  store.deleteOrphans(batch_id);
  return adopted;
}

/// Partition and account names go into #SBATCH lines: printable, no blanks, bounded.
void checkSlurmName(const std::string& value, const char* what) {
  constexpr std::size_t kMaxName = 256;
  DASH_THROW_UNLESS(value.size() <= kMaxName, std::string(what) + ": longer than 256 characters");
  for (const char c : value) {
    const auto u = static_cast<unsigned char>(c);
    DASH_THROW_UNLESS(u > 0x20 && u < 0x7f,
                      std::string(what) + ": only printable characters without spaces (no newline, no tab)");
  }
}

/// Checked before anything is written or submitted.
void checkSubmitOptions(const SlurmSubmitOptions& o) {
  checkSlurmName(o.partition, "--partition");
  checkSlurmName(o.account, "--account");
  DASH_THROW_UNLESS(o.max_parallel >= 0, "--max-parallel must not be negative");
  DASH_THROW_UNLESS(o.runs_per_task >= 1, "--runs-per-task must be at least 1");
}

Json optionsJson(const SlurmSubmitOptions& o, int runs_per_task, const std::string& executable) {
  return Json{{"partition", o.partition},
              {"account", o.account},
              {"max_parallel", o.max_parallel},
              {"runs_per_task", runs_per_task},
              {"executable", executable}};
}

/// The manifest's tasks: `runs` in chunks of `per_task`; the run keys of each task.
std::vector<std::vector<std::string>> fillManifest(SlurmManifest& manifest, const std::vector<RunSpec>& runs,
                                                   int per_task) {
  std::vector<std::vector<std::string>> task_keys;
  for (const auto& chunk : chunkRuns(runs.size(), per_task)) {
    std::vector<RunSpec> task_runs;
    std::vector<std::string> keys;
    for (int i : chunk) {
      task_runs.push_back(runs[static_cast<std::size_t>(i)]);
      keys.push_back(runs[static_cast<std::size_t>(i)].key);
    }
    manifest.tasks.push_back(std::move(task_runs));
    task_keys.push_back(std::move(keys));
  }
  return task_keys;
}

void writeJobScript(const std::string& script_path, const JobScript& job) {
  std::ofstream out(script_path, std::ios::binary | std::ios::trunc);
  DASH_THROW_UNLESS(out.good(), "cannot write " + script_path);
  out << formatJobScript(job);
}

/// Records a job sbatch accepted (and, for a new batch, the batch and its runs).
void recordJob(const std::string& db_path, const SlurmJobRecord& job,
               const std::vector<std::vector<std::string>>& task_keys, const std::vector<RunSpec>& runs,
               const BatchSpec* new_batch) {
  log::ResultsDb db(db_path);
  if (new_batch != nullptr) {
    db.putBatch(
        log::BatchRecord{.id = job.batch_id, .name = new_batch->name, .spec_json = new_batch->json, .status = "queued"});
    db.flush();
    BatchStore(db_path).addRuns(job.batch_id, runs);
  }
  SlurmStore(db_path).addJob(job, task_keys);
  db.setBatchStatus(job.batch_id, "submitted");
}

/// What Slurm says of one job's tasks: squeue first (asked once, unless every task is final), then
/// sacct (asked once, when squeue does not know a task), then the task's own state file.
class JobStates {
 public:
  JobStates(const SlurmClient& client, const SlurmJobRecord& job, bool all_final) : client_(client), job_(job) {
    if (!all_final) queue_ = client_.queue(job_.job_id);
  }

  /// The task's state now and where it comes from ("squeue", "sacct", "shard", or as recorded).
  SlurmState stateOf(const SlurmTaskRecord& t, std::string& source) {
    SlurmState state = slurmStateFromName(t.state);
    source = t.source;
    if (isFinal(state)) return state;
    if (queue_ && queue_->count(t.task) != 0) {
      state = queue_->at(t.task);
      source = "squeue";
    } else {
      if (!asked_accounting_) {
        accounting_ = client_.accounting(job_.job_id);
        asked_accounting_ = true;
      }
      if (accounting_ && accounting_->count(t.task) != 0) {
        state = accounting_->at(t.task);
        source = "sacct";
      } else if (queue_) {  // Slurm answered and has forgotten the task: it ended long enough ago
        state = stateFromTaskFile(job_.shard_dir, t.task, job_.cancelled);
        source = "shard";
      }
    }
    if (state == SlurmState::kUnknown) state = slurmStateFromName(t.state);
    return state;
  }

 private:
  const SlurmClient& client_;
  const SlurmJobRecord& job_;
  std::optional<std::map<int, SlurmState>> queue_;
  std::optional<std::map<int, SlurmState>> accounting_;
  bool asked_accounting_ = false;
};

/// One job's tasks into `view`: their states (changes recorded) and their shards (merged when changed).
void updateJob(log::ResultsDb& db, BatchStore& store, SlurmStore& slurm, const SlurmClient& client,
               const std::string& batch_id, const SlurmJobRecord& job, SlurmBatchView& view) {
  std::vector<SlurmTaskRecord> tasks = slurm.tasks(batch_id, job.submission);
  const bool all_final = std::all_of(tasks.begin(), tasks.end(),
                                     [](const SlurmTaskRecord& t) { return isFinal(slurmStateFromName(t.state)); });
  JobStates states(client, job, all_final);
  std::map<int, std::vector<std::string>> keys_of_task;
  for (const auto& [key, task] : slurm.runTasks(batch_id, job.submission)) keys_of_task[task].push_back(key);

  for (SlurmTaskRecord& t : tasks) {
    std::string source;
    const SlurmState state = states.stateOf(t, source);
    if (!isFinal(slurmStateFromName(t.state)) && (toString(state) != t.state || source != t.source)) {
      slurm.setTaskState(batch_id, job.submission, t.task, toString(state), source);
    }
    if (!isFinal(state)) view.active = true;

    const std::string shard = shardPath(job.shard_dir, t.task);
    const std::string stamp = shardStamp(shard);
    if (!stamp.empty() && stamp != t.shard_stamp) {
      db.mergeFrom(shard);
      db.flush();
      view.merged += adoptShardRuns(db, store, batch_id, shard);
      slurm.setShardStamp(batch_id, job.submission, t.task, stamp);
    }
    ++view.by_state[state];
    view.tasks.push_back(SlurmTaskView{.submission = job.submission,
                                       .job_id = job.job_id,
                                       .task = t.task,
                                       .state = state,
                                       .source = source,
                                       .keys = keys_of_task[t.task]});
  }
}

}  // namespace

SlurmBackend::SlurmBackend(std::string db_path, SlurmClient client)
    : db_path_(std::move(db_path)), client_(std::move(client)) {}

std::string SlurmBackend::submit(const BatchSpec& spec, const SlurmSubmitOptions& options) {
  DASH_THROW_UNLESS(spec.unknown_planners.empty(), "the spec names planners this build does not have");
  const std::string batch_id = options.batch_id.empty() ? newBatchId(spec.name) : options.batch_id;
  const std::vector<RunSpec> runs = expandRuns(spec);
  {
    const log::ResultsDb db(db_path_);
    for (const auto& b : db.listBatches()) {
      DASH_THROW_UNLESS(b.id != batch_id, "batch " + batch_id + " already exists in " + db_path_);
    }
  }
  // The batch and its runs are recorded only once sbatch has accepted the job: a refused
  // submission leaves no batch behind that the dashboard would offer to resume (issue 24).
  submitRuns(batch_id, spec.name, runs, spec.time_limit, spec.memory_limit_mb, options, 1, &spec);
  return batch_id;
}

std::string SlurmBackend::submitRuns(const std::string& batch_id, const std::string& name,
                                     const std::vector<RunSpec>& runs, double time_limit, double memory_limit_mb,
                                     const SlurmSubmitOptions& options, int submission, const BatchSpec* new_batch) {
  DASH_THROW_UNLESS(!runs.empty(), "a Slurm submission needs at least one run");
  checkSubmitOptions(options);
  DASH_THROW_UNLESS(onPath("sbatch"), "sbatch is not on the PATH (the Slurm backend needs Slurm's commands)");
  const fs::path root =
      fs::absolute(options.shard_dir.empty() ? fs::path(db_path_ + ".slurm") / batch_id : fs::path(options.shard_dir));
  const fs::path dir = root / ("s" + std::to_string(submission));
  const bool new_root = !fs::exists(root);
  fs::create_directories(dir);
  // Until sbatch accepted the job, a failure removes what this submission wrote.
  struct RemoveUnlessKept {
    fs::path path;
    bool keep = false;
    ~RemoveUnlessKept() {
      std::error_code ignored;
      if (!keep) fs::remove_all(path, ignored);
    }
  } written{new_root ? root : dir};
  const std::string executable = options.executable.empty() ? fs::read_symlink("/proc/self/exe").string()
                                                            : fs::absolute(options.executable).string();
  const int per_task = runsPerTask(runs.size(), options.runs_per_task);

  SlurmManifest manifest{.batch_id = batch_id, .name = name, .submission = submission, .shard_dir = dir.string()};
  const std::vector<std::vector<std::string>> task_keys = fillManifest(manifest, runs, per_task);
  const std::string manifest_path = (dir / "manifest.json").string();
  writeManifest(manifest_path, manifest);

  JobScript job;
  job.job_name = "dashbench-" + name;
  job.tasks = static_cast<int>(manifest.tasks.size());
  job.max_parallel = options.max_parallel;
  job.resources = taskResources(time_limit, memory_limit_mb, per_task);
  job.partition = options.partition;
  job.account = options.account;
  job.log_dir = dir.string();
  job.executable = executable;
  job.manifest = manifest_path;
  const std::string script_path = (dir / "job.sbatch").string();
  writeJobScript(script_path, job);
  const std::string job_id =
      client_.submit(script_path, {"--output=" + (dir / "slurm-%A_%a.out").string(), "--chdir=" + dir.string()});
  written.keep = true;
  try {
    recordJob(db_path_,
              SlurmJobRecord{.batch_id = batch_id,
                             .submission = submission,
                             .job_id = job_id,
                             .shard_dir = dir.string(),
                             .tasks = job.tasks,
                             .submitted = utcNow(),
                             .cancelled = false,
                             .options_json = optionsJson(options, per_task, executable).dump()},
              task_keys, runs, new_batch);
  } catch (...) {
    // A job nobody can follow: take it back from Slurm rather than let it run unrecorded.
    try {
      client_.cancel(job_id);
    } catch (const std::exception&) {
    }
    throw;
  }
  return job_id;
}

SlurmBatchView SlurmBackend::update(const std::string& batch_id) {
  log::ResultsDb db(db_path_);
  db.flush();
  BatchStore store(db_path_);
  SlurmStore slurm(db_path_);
  const std::vector<SlurmJobRecord> jobs = slurm.jobs(batch_id);
  DASH_THROW_UNLESS(!jobs.empty(), "batch " + batch_id + " was not submitted to Slurm");
  SlurmBatchView view;
  view.batch_id = batch_id;
  bool any_cancelled = false;
  for (const SlurmJobRecord& job : jobs) {
    any_cancelled = any_cancelled || job.cancelled;
    updateJob(db, store, slurm, client_, batch_id, job, view);
  }
  for (const StoredRun& r : store.runs(batch_id)) {
    ++view.runs;
    if (r.complete()) ++view.complete;
    view.run_status[r.spec.key] = r.status.value_or("");
  }
  std::string status = "submitted";
  if (!view.active) {
    if (view.complete == view.runs) {
      status = "finished";
    } else {
      status = any_cancelled ? "cancelled" : "interrupted";
    }
  }
  std::string previous;
  for (const auto& b : db.listBatches()) {
    if (b.id == batch_id) previous = b.status;
  }
  if (previous != status) db.setBatchStatus(batch_id, status);
  view.status = status;
  return view;
}

void SlurmBackend::cancel(const std::string& batch_id) {
  const SlurmBatchView view = update(batch_id);
  DASH_THROW_UNLESS(view.active, "batch " + batch_id + " has no tasks left in Slurm");
  std::map<int, std::string> active_jobs;
  for (const SlurmTaskView& t : view.tasks) {
    if (!isFinal(t.state)) active_jobs[t.submission] = t.job_id;
  }
  SlurmStore slurm(db_path_);
  for (const auto& [submission, job_id] : active_jobs) {
    slurm.setCancelled(batch_id, submission);  // first: a task gone before the next update counts as cancelled
    client_.cancel(job_id);
  }
}

std::int64_t SlurmBackend::resume(const std::string& batch_id, const SlurmSubmitOptions& options) {
  const SlurmBatchView view = update(batch_id);
  DASH_THROW_UNLESS(!view.active, "batch " + batch_id + " still has tasks in Slurm: wait for them, or cancel it first");
  std::vector<RunSpec> missing;
  std::string name;
  SlurmSubmitOptions merged = options;
  int last_submission = 0;
  {
    log::ResultsDb db(db_path_);
    db.flush();
    BatchStore store(db_path_);
    for (const auto& b : db.listBatches()) {
      if (b.id == batch_id) name = b.name;
    }
    for (const StoredRun& r : store.runs(batch_id)) {
      if (r.complete()) continue;
      if (!r.run_uuid.empty()) store.deleteRun(r.run_uuid);  // its cancelled or partial row is re-run
      missing.push_back(r.spec);
    }
    const std::vector<SlurmJobRecord> jobs = SlurmStore(db_path_).jobs(batch_id);
    last_submission = jobs.back().submission;
    const Json last = Json::parse(jobs.back().options_json);
    if (merged.partition.empty()) merged.partition = last.value("partition", "");
    if (merged.account.empty()) merged.account = last.value("account", "");
    if (merged.max_parallel == 0) merged.max_parallel = last.value("max_parallel", 0);
    if (merged.runs_per_task == 1) merged.runs_per_task = last.value("runs_per_task", 1);
    if (merged.executable.empty()) merged.executable = last.value("executable", "");
    if (merged.shard_dir.empty()) merged.shard_dir = fs::path(jobs.back().shard_dir).parent_path().string();
  }
  DASH_THROW_UNLESS(!missing.empty(), "batch " + batch_id + " has no missing runs");
  submitRuns(batch_id, name, missing, missing.front().time_limit, missing.front().memory_limit_mb, merged,
             last_submission + 1);
  return static_cast<std::int64_t>(missing.size());
}

bool SlurmBackend::isSlurmBatch(const std::string& db_path, const std::string& batch_id) {
  if (!fs::exists(db_path)) return false;
  return !SlurmStore(db_path, log::OpenMode::ReadOnly).jobs(batch_id).empty();
}

std::string formatSlurmView(const SlurmBatchView& view, bool per_run) {
  std::ostringstream s;
  std::map<int, std::string> job_of;
  for (const SlurmTaskView& t : view.tasks) job_of[t.submission] = t.job_id;
  s << "slurm " << view.batch_id << ": " << view.status << ", " << view.complete << "/" << view.runs
    << " runs with a result; array tasks:";
  bool first = true;
  for (const auto& [state, n] : view.by_state) {
    s << (first ? " " : ", ") << n << " " << toString(state);
    first = false;
  }
  s << "  (job";
  for (const auto& [submission, job] : job_of) s << " " << job;
  s << ")\n";
  if (!per_run) return s.str();
  for (const SlurmTaskView& t : view.tasks) {
    s << "  " << t.job_id << "_" << t.task << "  " << toString(t.state);
    if (!t.source.empty()) s << " (" << t.source << ")";
    s << "\n";
    for (const std::string& key : t.keys) {
      const auto it = view.run_status.find(key);
      const std::string status = it == view.run_status.end() || it->second.empty() ? "-" : it->second;
      s << "      " << status << "  " << key << "\n";
    }
  }
  return s.str();
}

}  // namespace dash::batch
