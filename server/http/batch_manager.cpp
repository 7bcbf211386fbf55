#include "server/http/batch_manager.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include "engine/log/results_db.h"
#include "server/batch/batch_spec.h"
#include "server/batch/batch_store.h"
#include "server/batch/slurm_backend.h"
#include "server/batch/slurm_store.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"

namespace dash::http {

namespace {

constexpr auto kLoopPeriod = std::chrono::milliseconds(200);
constexpr auto kSlurmPollPeriod = std::chrono::seconds(5);  ///< squeue is a request to the controller
constexpr int kBusyTimeoutMs = 15000;  ///< a submit's wait for the runners' writes (BatchStore's too)

Json progressJson(const batch::BatchProgress& p) {
  Json j = {{"total", p.total},          {"done", p.done},         {"solved", p.solved},
            {"failed", p.failed},        {"timeouts", p.timeouts}, {"crashed", p.crashed},
            {"cancelled", p.cancelled},  {"running", p.running},   {"remaining", p.remaining},
            {"skipped", p.skipped},      {"elapsed", p.elapsed},   {"eta", p.eta < 0 ? Json(nullptr) : Json(p.eta)},
            {"cancelling", p.cancelling}};
  // The running runs, each with its planner's latest long-phase progress (conflict resolution: steps
  // scheduled of the plan's, the step's robots, steps per second), null before the first, and the
  // phase it is in now (null before its first phase).
  Json active = Json::array();
  for (const batch::ActiveRun& a : p.active) {
    Json work = nullptr;
    if (a.work) {
      work = {{"phase", log::toString(a.work->phase)}, {"done", a.work->done},     {"total", a.work->total},
              {"rate", a.work->rate},                  {"current", a.work->current}};
    }
    active.push_back({{"key", a.key},
                      {"uuid", a.uuid},
                      {"seconds", a.seconds},
                      {"work", work},
                      {"phase", a.phase ? Json(log::toString(*a.phase)) : Json(nullptr)}});
  }
  j["active"] = std::move(active);
  if (p.finished) {
    j["finished"] = {{"key", p.finished->key},
                     {"uuid", p.finished->uuid},
                     {"status", log::toString(p.finished->status)},
                     {"seconds", p.finished->seconds},
                     {"error", p.finished->error}};
  }
  return j;
}

/// Progress of a batch this server does not run, from its stored rows.
Json storedProgressJson(const batch::BatchInfo& b) {
  auto count = [&](const char* s) -> std::int64_t {
    const auto it = b.by_status.find(s);
    return it == b.by_status.end() ? 0 : it->second;
  };
  const std::int64_t solved = count("solved");
  const std::int64_t timeouts = count("timeout");
  const std::int64_t crashed = count("crashed");
  const std::int64_t failed = timeouts + crashed + count("infeasible");
  const std::int64_t done = std::max<std::int64_t>(0, b.total - b.pending);
  return {{"total", b.total},
          {"done", done},
          {"solved", solved},
          {"failed", failed},
          {"timeouts", timeouts},
          {"crashed", crashed},
          {"cancelled", count("cancelled")},
          {"running", b.status == "running" ? count("running") : 0},
          {"remaining", b.total - done},
          {"skipped", 0},
          {"elapsed", nullptr},
          {"eta", nullptr},
          {"cancelling", false}};
}

}  // namespace

BatchManager::BatchManager(BatchManagerOptions options, EventHub& hub) : options_(std::move(options)), hub_(hub) {
  thread_ = std::thread([this] { loop(); });
}

BatchManager::~BatchManager() { shutdown(); }

int BatchManager::checkedWorkers(int workers) const {
  if (workers < 1 || workers > options_.max_workers) {
    throw HttpError(400, "workers: " + std::to_string(workers) + " is out of range 1.." +
                             std::to_string(options_.max_workers) + " (this server's limit)");
  }
  return workers;
}

batch::SpecOptions BatchManager::specOptions() const {
  return {.max_runs = options_.max_runs, .max_runs_advice = "this server's limit: dashbench serve --max-runs"};
}

std::string BatchManager::validateJson(const std::string& spec_json, std::size_t max_keys) const {
  const batch::BatchSpec spec = batch::parseBatchSpec(spec_json, "spec", specOptions());
  // The preview's keys only: the grid is counted from its sizes, never expanded here.
  Json keys = Json::array();
  for (const batch::RunSpec& r : batch::expandRuns(spec, max_keys)) keys.push_back(r.key);
  return jsonText(
      Json{{"name", spec.name}, {"runs", batch::countRuns(spec)}, {"keys", keys}, {"time_limit", spec.time_limit}});
}

SubmitOutcome BatchManager::submit(const std::string& spec_json, int workers) {
  checkedWorkers(workers);
  const batch::BatchSpec spec = batch::parseBatchSpec(spec_json, "spec", specOptions());
  const std::vector<batch::RunSpec> runs = batch::expandRuns(spec);
  const std::string id = batch::newBatchId(spec.name);
  {
    // One submit writes at a time: 40 at once, each a writer of its own, waited on each other's locks
    // until some gave up with "database is locked" (issue 40). The runners' writes are short
    // transactions, which the busy timeout outwaits.
    std::lock_guard submitting(submit_mutex_);
    // Recorded before it runs (what BatchRunner::start would do), so a queued batch survives a restart.
    {
      log::ResultsDb db(options_.db_path, log::OpenMode::ReadWrite, log::DbOptions{.busy_timeout_ms = kBusyTimeoutMs});
      db.putBatch(log::BatchRecord{.id = id, .name = spec.name, .spec_json = spec.json, .status = "queued"});
    }
    batch::BatchStore store(options_.db_path);
    store.addRuns(id, runs);
  }
  {
    std::lock_guard lock(mutex_);
    DASH_THROW_UNLESS(!stopping_, "the server is shutting down");
    queue_.push_back(Queued{.batch_id = id, .workers = workers});
  }
  cv_.notify_all();
  publishBatch(id);
  return SubmitOutcome{.batch_id = id, .runs = runs.size(), .status = "queued"};
}

bool BatchManager::slurmAvailable() const { return batch::SlurmClient::available(); }

SubmitOutcome BatchManager::submitSlurm(const std::string& spec_json, const SlurmRequest& request) {
  if (!slurmAvailable()) throw HttpError(400, "backend: sbatch is not on this server's PATH");
  if (request.max_parallel < 0) throw HttpError(400, "max_parallel: must not be negative");
  const batch::BatchSpec spec = batch::parseBatchSpec(spec_json, "spec", specOptions());
  batch::SlurmSubmitOptions o;
  o.partition = request.partition;
  o.account = request.account;
  o.max_parallel = request.max_parallel;
  o.executable = options_.executable;
  const std::string id = batch::SlurmBackend(options_.db_path).submit(spec, o);
  publishBatch(id);
  return SubmitOutcome{.batch_id = id, .runs = batch::countRuns(spec), .status = "submitted"};
}

void BatchManager::pollSlurm() {
  if (std::chrono::steady_clock::now() - last_slurm_poll_ < kSlurmPollPeriod) return;
  last_slurm_poll_ = std::chrono::steady_clock::now();
  try {
    std::vector<std::string> ids;
    {
      const log::ResultsDb db(options_.db_path, log::OpenMode::ReadOnly);
      const batch::SlurmStore store(options_.db_path, log::OpenMode::ReadOnly);
      const std::vector<std::string> slurm_ids = store.batchIds();
      for (const log::BatchRecord& b : db.listBatches()) {
        if (b.status == "submitted" && std::find(slurm_ids.begin(), slurm_ids.end(), b.id) != slurm_ids.end()) {
          ids.push_back(b.id);
        }
      }
    }
    for (const std::string& id : ids) {
      const batch::SlurmBatchView v = batch::SlurmBackend(options_.db_path).update(id);
      if (v.merged > 0 || !v.active) publishBatch(id);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dashbench serve: following Slurm batches: %s\n", e.what());
  }
}

void BatchManager::cancel(const std::string& batch_id) {
  if (batch::SlurmBackend::isSlurmBatch(options_.db_path, batch_id)) {
    try {
      batch::SlurmBackend(options_.db_path).cancel(batch_id);
    } catch (const InputError& e) {
      throw HttpError(409, e.what());
    }
    publishBatch(batch_id);
    return;
  }
  bool was_queued = false;
  {
    std::lock_guard lock(mutex_);
    const auto q = std::find_if(queue_.begin(), queue_.end(), [&](const Queued& x) { return x.batch_id == batch_id; });
    if (q != queue_.end()) {
      queue_.erase(q);
      was_queued = true;
    } else if (const auto it = active_.find(batch_id); it != active_.end()) {
      it->second.cancel_requested = true;
      if (it->second.runner) it->second.runner->cancel();  // async-signal-safe: just a flag and a pipe
    }
    if (!was_queued && active_.count(batch_id) != 0) {
      cv_.notify_all();
      publishBatch(batch_id);
      return;
    }
  }
  if (was_queued) {
    // A queued batch that never started: it stays resumable.
    log::ResultsDb db(options_.db_path);
    db.setBatchStatus(batch_id, "cancelled");
    publishBatch(batch_id);
    return;
  }
  const std::vector<batch::BatchInfo> info = batch::listBatchInfo(options_.db_path);
  const auto b = std::find_if(info.begin(), info.end(), [&](const auto& x) { return x.record.id == batch_id; });
  if (b == info.end()) throw HttpError(404, "no batch " + batch_id);
  if (b->status == "running") {
    throw HttpError(409, "batch " + batch_id + " is run by another process (pid " +
                             std::to_string(b->runner ? b->runner->pid : 0) + "), not by this server; stop it there");
  }
  throw HttpError(409, "batch " + batch_id + " is not running (status " +
                           (b->status == "queued" ? std::string("interrupted") : b->status) + ")");
}

void BatchManager::resume(const std::string& batch_id, int workers) {
  checkedWorkers(workers);
  if (batch::SlurmBackend::isSlurmBatch(options_.db_path, batch_id)) {
    try {
      batch::SlurmBackend(options_.db_path).resume(batch_id);  // the last submission's options
    } catch (const InputError& e) {
      throw HttpError(409, e.what());
    }
    publishBatch(batch_id);
    return;
  }
  {
    std::lock_guard lock(mutex_);
    const bool queued =
        std::any_of(queue_.begin(), queue_.end(), [&](const Queued& x) { return x.batch_id == batch_id; });
    if (queued || active_.count(batch_id) != 0) {
      throw HttpError(409, "batch " + batch_id + " is already " + (queued ? "queued" : "running") + " in this server");
    }
  }
  const std::vector<batch::BatchInfo> info = batch::listBatchInfo(options_.db_path);
  const auto b = std::find_if(info.begin(), info.end(), [&](const auto& x) { return x.record.id == batch_id; });
  if (b == info.end()) throw HttpError(404, "no batch " + batch_id);
  if (b->status == "running") {
    throw HttpError(409, "batch " + batch_id + " is still being run by process " +
                             std::to_string(b->runner ? b->runner->pid : 0) + "; nothing to resume");
  }
  if (b->total == 0) throw HttpError(409, "batch " + batch_id + " has no stored run list; it cannot be resumed");
  if (b->pending == 0) throw HttpError(409, "batch " + batch_id + " has every run finished; nothing to resume");
  {
    std::lock_guard lock(mutex_);
    DASH_THROW_UNLESS(!stopping_, "the server is shutting down");
    queue_.push_back(Queued{.batch_id = batch_id, .workers = workers});
  }
  cv_.notify_all();
  publishBatch(batch_id);
}

void BatchManager::onProgress(const batch::BatchProgress& p) {
  {
    std::lock_guard lock(mutex_);
    if (const auto it = active_.find(p.batch_id); it != active_.end()) it->second.progress = p;
  }
  Json j = {{"id", p.batch_id}, {"status", p.cancelling ? "cancelling" : "running"}, {"progress", progressJson(p)}};
  hub_.publish("batch", p.batch_id, jsonText(j));
}

void BatchManager::publishBatch(const std::string& batch_id) const {
  // The page refetches the list on a "batches" event; "batch" events carry live progress only.
  hub_.publish("batches", batch_id, jsonText(Json{{"id", batch_id}}));
}

void BatchManager::startQueued(const Queued& q) {
  auto runner = std::make_unique<batch::BatchRunner>();
  batch::RunnerOptions ro;
  ro.workers = q.workers;
  ro.executable = options_.executable;
  try {
    runner->resume(q.batch_id, options_.db_path, ro, [this](const batch::BatchProgress& p) { onProgress(p); });
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dashbench serve: batch %s could not start: %s\n", q.batch_id.c_str(), e.what());
    {
      std::lock_guard lock(mutex_);
      active_.erase(q.batch_id);
    }
    hub_.publish("batch", q.batch_id,
                 jsonText(Json{{"id", q.batch_id}, {"status", "interrupted"}, {"error", e.what()}}));
    publishBatch(q.batch_id);
    return;
  }
  bool cancel_now = false;
  {
    std::lock_guard lock(mutex_);
    Active& a = active_[q.batch_id];
    a.runner = std::move(runner);
    cancel_now = a.cancel_requested || stopping_;
    if (cancel_now) a.runner->cancel();
  }
  publishBatch(q.batch_id);
}

void BatchManager::loop() {
  std::unique_lock lock(mutex_);
  while (true) {
    cv_.wait_for(lock, kLoopPeriod);
    // Reap finished runners (wait() outside the lock: their last progress callback takes it).
    struct Ended {
      std::string id;
      std::unique_ptr<batch::BatchRunner> runner;
      bool stopped_by_server = false;  ///< cancelled because the server stops, not by a person
    };
    std::vector<Ended> ended;
    for (auto it = active_.begin(); it != active_.end();) {
      if (it->second.runner && it->second.runner->done()) {
        ended.push_back(Ended{it->first, std::move(it->second.runner), stopping_ && !it->second.cancel_requested});
        it = active_.erase(it);
      } else {
        ++it;
      }
    }
    const bool stop = stopping_ && active_.empty();
    const bool poll_slurm = !stopping_;
    std::vector<Queued> to_start;
    while (!stopping_ && !queue_.empty() && static_cast<int>(active_.size()) < options_.max_running) {
      to_start.push_back(queue_.front());
      queue_.pop_front();
      active_[to_start.back().batch_id].workers = to_start.back().workers;  // holds the slot while starting
    }
    lock.unlock();
    for (Ended& e : ended) {
      const std::string& id = e.id;
      batch::BatchResult r = e.runner->wait();
      if (e.stopped_by_server && r.status == "cancelled") {
        // Nobody cancelled it: the server went away. After the next start it reads as interrupted.
        try {
          log::ResultsDb(options_.db_path).setBatchStatus(id, "interrupted");
          r.status = "interrupted";
        } catch (const std::exception& err) {
          std::fprintf(stderr, "dashbench serve: batch %s: %s\n", id.c_str(), err.what());
        }
      }
      Json j = {{"id", id}, {"status", r.status}, {"progress", progressJson(r.progress)}};
      if (!r.error.empty()) j["error"] = r.error;
      hub_.publish("batch", id, jsonText(j));
      publishBatch(id);
    }
    for (const Queued& q : to_start) startQueued(q);
    if (poll_slurm) pollSlurm();
    lock.lock();
    if (stop) return;
  }
}

void BatchManager::shutdown() {
  {
    std::lock_guard lock(mutex_);
    if (!thread_.joinable()) return;
    stopping_ = true;
    queue_.clear();  // stored as 'queued': shown as interrupted after the restart, resumable
    for (auto& [id, a] : active_) {
      if (a.runner) a.runner->cancel();
    }
  }
  cv_.notify_all();
  thread_.join();
}

std::string BatchManager::batchesJson() const {
  const std::vector<batch::BatchInfo> infos = batch::listBatchInfo(options_.db_path);
  // Slurm batches: their array tasks per Slurm state, as last seen by pollSlurm (no Slurm call here).
  std::map<std::string, Json> slurm_states;
  {
    const batch::SlurmStore slurm(options_.db_path, log::OpenMode::ReadOnly);
    for (const std::string& id : slurm.batchIds()) {
      Json states = Json::object();
      for (const batch::SlurmJobRecord& job : slurm.jobs(id)) {
        for (const batch::SlurmTaskRecord& t : slurm.tasks(id, job.submission)) {
          states[t.state] = states.value(t.state, 0) + 1;
        }
      }
      slurm_states[id] = std::move(states);
    }
  }
  std::lock_guard lock(mutex_);
  Json list = Json::array();
  for (const batch::BatchInfo& b : infos) {
    Json j = {{"id", b.record.id}, {"name", b.record.name}, {"created", b.record.created},
              {"total", b.total},  {"pending", b.pending},  {"by_status", b.by_status}};
    std::string status = b.status;
    const bool queued_here =
        std::any_of(queue_.begin(), queue_.end(), [&](const Queued& q) { return q.batch_id == b.record.id; });
    const auto act = active_.find(b.record.id);
    if (queued_here) {
      status = "queued";
    } else if (act != active_.end()) {
      status = act->second.cancel_requested || (act->second.progress && act->second.progress->cancelling) ? "cancelling"
                                                                                                          : "running";
      j["workers"] = act->second.workers;
    } else if (status == "queued") {
      status = "interrupted";  // recorded by a server that stopped before it could start it
    }
    j["status"] = status;
    j["here"] = queued_here || act != active_.end();
    j["progress"] =
        act != active_.end() && act->second.progress ? progressJson(*act->second.progress) : storedProgressJson(b);
    j["cancellable"] = queued_here || act != active_.end();
    j["resumable"] = !j["here"].get<bool>() && status != "running" && b.pending > 0 && b.total > 0;
    j["backend"] = "local";
    if (const auto slurm = slurm_states.find(b.record.id); slurm != slurm_states.end()) {
      j["backend"] = "slurm";
      j["slurm"] = slurm->second;
      j["cancellable"] = status == "submitted";
      j["resumable"] = status != "submitted" && b.pending > 0 && b.total > 0;
    }
    if (b.runner) {
      j["runner"] = {{"pid", b.runner->pid},
                     {"host", b.runner->host},
                     {"started", b.runner->started},
                     {"heartbeat_age", b.runner->age()},
                     {"workers", b.runner->workers}};
    }
    list.push_back(std::move(j));
  }
  std::stable_sort(list.begin(), list.end(), [](const Json& a, const Json& b) {
    return a["created"].get<std::string>() > b["created"].get<std::string>();
  });
  return jsonText(Json{{"batches", list}});
}

std::string BatchManager::batchJson(const std::string& batch_id) const {
  Json all = Json::parse(batchesJson());
  Json out;
  for (const Json& b : all["batches"]) {
    if (b["id"] == batch_id) out = b;
  }
  if (out.is_null()) throw HttpError(404, "no batch " + batch_id);
  const log::ResultsDb db(options_.db_path, log::OpenMode::ReadOnly);
  for (const log::BatchRecord& r : db.listBatches()) {
    if (r.id == batch_id) out["spec"] = parseStored(r.spec_json);
  }
  const batch::BatchStore store(options_.db_path, log::OpenMode::ReadOnly);
  Json runs = Json::array();
  for (const batch::StoredRun& r : store.runs(batch_id)) {
    // What the run is (family, parameters, seed, configuration), so that a page can place a run that
    // has no dash_runs row, such as one the axis stop rule skipped, on its figures.
    Json params = Json::object();
    for (const auto& [name, value] : r.spec.params) params[name] = value;
    const std::string status = !r.skipped.empty() ? "skipped" : r.status.value_or("pending");
    runs.push_back({{"key", r.spec.key},
                    {"uuid", r.run_uuid.empty() ? Json(nullptr) : Json(r.run_uuid)},
                    {"status", status},
                    {"attempts", r.attempts},
                    {"error", r.error},
                    {"skipped", r.skipped.empty() ? Json(nullptr) : Json(r.skipped)},
                    {"family", r.spec.family},
                    {"params", std::move(params)},
                    {"seed", r.spec.seed},
                    {"planner", r.spec.planner},
                    {"config", r.spec.label},
                    {"stop_axis", r.spec.stop_axis.empty() ? Json(nullptr) : Json(r.spec.stop_axis)}});
  }
  out["runs"] = std::move(runs);
  return jsonText(out);
}

}  // namespace dash::http
