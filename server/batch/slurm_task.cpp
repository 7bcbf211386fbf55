#include "server/batch/slurm_task.h"

#include <sqlite3.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"
#include "server/batch/batch_runner.h"
#include "server/batch/batch_store.h"
#include "server/batch/progress_printer.h"

namespace dash::batch {

namespace fs = std::filesystem;
namespace sql = log::sql;
using Json = nlohmann::json;

namespace {

constexpr const char* kManifestFormat = "dashbench.slurm-manifest/1";
constexpr int kExitCancelled = 130;

constexpr const char* kShardTable =
    "CREATE TABLE IF NOT EXISTS dash_slurm_shard_runs (run_key TEXT PRIMARY KEY, run_uuid TEXT NOT NULL)";

/// The final statuses a requeued task keeps (as StoredRun::complete: not running, not cancelled).
bool isFinalStatus(const std::string& status) {
  return status == "solved" || status == "timeout" || status == "infeasible" || status == "crashed";
}

void writeFileAtomically(const std::string& path, const std::string& text) {
  const std::string part = path + ".part";
  {
    std::ofstream out(part, std::ios::binary | std::ios::trunc);
    DASH_THROW_UNLESS(out.good(), "cannot write " + part);
    out << text;
    out.flush();
    DASH_THROW_UNLESS(out.good(), "cannot write " + part);
  }
  fs::rename(part, path);
}

void removeDbFiles(const std::string& path) {
  std::error_code ec;
  for (const char* suffix : {"", "-wal", "-shm", "-journal"}) fs::remove(path + suffix, ec);
}

/// The run's row in the task's shard: its uuid and status, if the shard has one.
struct ShardRun {
  std::string uuid;
  std::string status;
};

class Shard {
 public:
  Shard(const std::string& local_path) : db_(local_path) {
    db_.flush();
    sql::Connection c = sql::open(local_path, SQLITE_OPEN_READWRITE);
    sql::exec(c.get(), kShardTable);
  }

  std::optional<ShardRun> find(const std::string& key) const {
    const log::SqlRows rows = db_.select(
        "SELECT s.run_uuid, r.status FROM dash_slurm_shard_runs s LEFT JOIN dash_runs r ON r.uuid = s.run_uuid "
        "WHERE s.run_key = ?",
        {key});
    if (rows.rows.empty()) return std::nullopt;
    ShardRun r;
    r.uuid = std::get<std::string>(rows.rows[0][0]);
    if (const auto* s = std::get_if<std::string>(&rows.rows[0][1])) r.status = *s;
    return r;
  }

  /// Merges a finished run's file and records key -> uuid, dropping the key's earlier attempt.
  void add(const std::string& key, const std::string& uuid, const std::string& run_db) {
    const std::optional<ShardRun> previous = find(key);
    db_.mergeFrom(run_db);
    db_.flush();
    if (previous && previous->uuid != uuid) BatchStore(db_.path()).deleteRun(previous->uuid);
    sql::Connection c = sql::open(db_.path(), SQLITE_OPEN_READWRITE);
    sql::Statement st(c.get(), "INSERT OR REPLACE INTO dash_slurm_shard_runs (run_key, run_uuid) VALUES (?, ?)");
    st.bind(1, key).bind(2, uuid).run();
  }

  /// Copies the shard to `path` (.part, rollback-journal mode, then rename).
  void publish(const std::string& path) {
    db_.flush();
    const std::string part = path + ".part";
    removeDbFiles(part);
    {
      sql::Connection c = sql::open(db_.path(), SQLITE_OPEN_READONLY);
      sql::Statement st(c.get(), "VACUUM INTO ?");
      st.bind(1, part).run();
    }
    {
      sql::Connection c = sql::open(part, SQLITE_OPEN_READWRITE);
      sql::exec(c.get(), "PRAGMA journal_mode = DELETE");
    }
    fs::rename(part, path);
  }

 private:
  log::ResultsDb db_;
};

std::string scratchRoot(const std::string& requested) {
  if (!requested.empty()) return requested;
  const char* tmp = std::getenv("TMPDIR");
  return tmp != nullptr && *tmp != '\0' ? tmp : "/tmp";
}

}  // namespace

void writeManifest(const std::string& path, const SlurmManifest& manifest) {
  Json tasks = Json::array();
  for (const auto& runs : manifest.tasks) {
    Json list = Json::array();
    for (const RunSpec& r : runs) list.push_back(Json::parse(r.toJson()));
    tasks.push_back(std::move(list));
  }
  const Json doc = {{"format", kManifestFormat},           {"batch_id", manifest.batch_id},
                    {"name", manifest.name},               {"submission", manifest.submission},
                    {"shard_dir", manifest.shard_dir},     {"tasks", std::move(tasks)}};
  writeFileAtomically(path, doc.dump(1) + "\n");
}

SlurmManifest readManifest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  DASH_THROW_UNLESS(in.good(), "cannot read the manifest " + path);
  std::stringstream text;
  text << in.rdbuf();
  try {
    const Json doc = Json::parse(text.str());
    DASH_THROW_UNLESS(doc.value("format", "") == kManifestFormat, path + ": not a " + kManifestFormat + " file");
    SlurmManifest m;
    m.batch_id = doc.at("batch_id").get<std::string>();
    m.name = doc.at("name").get<std::string>();
    m.submission = doc.at("submission").get<int>();
    m.shard_dir = doc.at("shard_dir").get<std::string>();
    for (const Json& list : doc.at("tasks")) {
      std::vector<RunSpec> runs;
      for (const Json& r : list) runs.push_back(RunSpec::fromJson(r.dump()));
      m.tasks.push_back(std::move(runs));
    }
    return m;
  } catch (const Json::exception& e) {
    throw InputError(path + ": " + e.what());
  }
}

std::string shardPath(const std::string& shard_dir, int task) {
  return shard_dir + "/task-" + std::to_string(task) + ".db";
}

std::string taskStatePath(const std::string& shard_dir, int task) {
  return shard_dir + "/task-" + std::to_string(task) + ".state";
}

BatchSpec singleRunSpec(const RunSpec& run, const std::string& batch_name) {
  BatchSpec spec;
  spec.name = batch_name;
  spec.time_limit = run.time_limit;
  spec.memory_limit_mb = run.memory_limit_mb;
  ScenarioEntry scenario;
  scenario.family = run.family;
  for (const auto& [name, value] : run.params) scenario.params.emplace_back(name, std::vector<int>{value});
  spec.scenarios.push_back(std::move(scenario));
  spec.planners.push_back(PlannerEntry{.name = run.planner,
                                       .label = run.label,
                                       .settings_json = run.settings_json,
                                       .task_only = run.task_only,
                                       .test_fault = run.test_fault});
  spec.seeds = {run.seed};
  spec.json = "{}";
  return spec;
}

int SlurmTask::run() {
  const SlurmManifest manifest = readManifest(options_.manifest);
  DASH_THROW_UNLESS(options_.task >= 0 && options_.task < static_cast<int>(manifest.tasks.size()),
                    "task " + std::to_string(options_.task) + " is not in " + options_.manifest + " (" +
                        std::to_string(manifest.tasks.size()) + " tasks)");
  const std::vector<RunSpec>& runs = manifest.tasks[static_cast<std::size_t>(options_.task)];
  const std::string published = shardPath(manifest.shard_dir, options_.task);
  const fs::path scratch = fs::path(scratchRoot(options_.work_dir)) /
                           ("dashbench-slurm-" + std::to_string(getpid()) + "-" + std::to_string(options_.task));
  fs::create_directories(scratch);
  const std::string local = (scratch / "shard.db").string();
  removeDbFiles(local);
  if (fs::exists(published)) fs::copy_file(published, local);  // a requeued task goes on from there

  std::fprintf(stderr, "dashbench slurm task %d of batch %s (submission %d): %zu run%s\n", options_.task,
               manifest.batch_id.c_str(), manifest.submission, runs.size(), runs.size() == 1 ? "" : "s");
  int done = 0;
  {
    Shard shard(local);
    for (const RunSpec& r : runs) {
      if (cancelled_.load()) break;
      const auto held = shard.find(r.key);
      if (held && isFinalStatus(held->status)) {
        std::fprintf(stderr, "  %s: %s (from an earlier attempt of this task)\n", r.key.c_str(), held->status.c_str());
        ++done;
        continue;
      }
      const std::string run_db = (scratch / ("run-" + std::to_string(r.ordinal) + ".db")).string();
      removeDbFiles(run_db);
      RunnerOptions options;
      options.executable = options_.executable;
      options.batch_id = manifest.batch_id;
      BatchResult result;
      {
        BatchRunner runner;
        runner.start(singleRunSpec(r, manifest.name), run_db, options, [](const BatchProgress& p) {
          if (p.finished) std::fprintf(stderr, "  %s\n", ProgressPrinter::formatLine(p, *p.finished).c_str());
        });
        runner_.store(&runner);
        if (cancelled_.load()) runner.cancel();  // a signal between start() and the store above
        result = runner.wait();
        runner_.store(nullptr);
      }
      DASH_THROW_UNLESS(result.status != "interrupted", "the runner failed on " + r.key + ": " + result.error);
      const std::vector<StoredRun> stored = BatchStore(run_db, log::OpenMode::ReadOnly).runs(manifest.batch_id);
      if (!stored.empty() && !stored.front().run_uuid.empty()) {
        shard.add(r.key, stored.front().run_uuid, run_db);
        shard.publish(published);
        if (stored.front().complete()) ++done;
      }
      removeDbFiles(run_db);
    }
    shard.publish(published);
  }
  removeDbFiles(local);
  std::error_code ec;
  fs::remove_all(scratch, ec);
  const bool stopped = cancelled_.load();
  writeFileAtomically(taskStatePath(manifest.shard_dir, options_.task), stopped ? "stopped\n" : "completed\n");
  std::fprintf(stderr, "dashbench slurm task %d: %d of %zu runs with a result%s\n", options_.task, done, runs.size(),
               stopped ? " (stopped)" : "");
  return stopped ? kExitCancelled : 0;
}

void SlurmTask::cancel() noexcept {
  cancelled_.store(true);
  BatchRunner* runner = runner_.load();
  if (runner != nullptr) runner->cancel();
}

}  // namespace dash::batch
