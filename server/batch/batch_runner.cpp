#include "server/batch/batch_runner.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <list>
#include <random>
#include <system_error>

#include "engine/core/stopwatch.h"
#include "engine/log/sqlite_recorder.h"
#include "server/batch/axis_stop.h"
#include "server/batch/batch_store.h"
#include "server/batch/run_child.h"
#include "server/batch/run_process.h"
#include "server/batch/run_protocol.h"
#include "engine/core/host_info.h"

namespace dash::batch {
namespace {

/// The run's settings as given plus "parameters": every named planner parameter's effective value
/// (defaults included), so that the results database holds the full set each run planned with.
std::string withEffectiveParameters(const std::string& planner, const std::string& settings_json) {
  try {
    const ParamValues effective = resolveParameters(planner, plannerParameterSettings(settings_json));
    std::string out = settings_json.empty() || settings_json == "{}" ? "{" : settings_json.substr(0, settings_json.size() - 1) + ",";
    return out + "\"parameters\":" + parametersJson(effective) + "}";
  } catch (const std::exception&) {
    return settings_json;  // a planner this build does not know (allow_unknown_planners)
  }
}

using Seconds = std::chrono::duration<double>;
using std::chrono::milliseconds;

/// SIGTERM for time comes at time_limit * this + RunnerOptions::time_slack: a planner that honours
/// its deadline returns first, with its own (complete) result.
constexpr double kTimeLimitMargin = 1.05;
constexpr milliseconds kPollInterval{250};        ///< at most between two looks at the timers
constexpr milliseconds kFlushInterval{500};       ///< recorded events become visible to readers
constexpr milliseconds kHeartbeatInterval{2000};  ///< see kStaleHeartbeatSeconds
constexpr milliseconds kProgressInterval{1000};   ///< progress callbacks while nothing else happens

std::string randomHex(int digits) {
  static thread_local std::mt19937_64 rng(std::random_device{}() ^
                                          static_cast<std::uint64_t>(Clock::now().time_since_epoch().count()));
  static constexpr char kHex[] = "0123456789abcdef";
  std::string s;
  for (int i = 0; i < digits; ++i) s.push_back(kHex[rng() & 15u]);
  return s;
}

std::string formatSeconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", s);
  return buf;
}


}  // namespace

std::string newBatchId(const std::string& name) {
  std::string clean;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    clean.push_back(ok ? c : '-');
  }
  if (clean.empty()) clean = "batch";
  if (clean.size() > 40) clean.resize(40);
  return clean + "-" + utcNow("%Y%m%d-%H%M%S") + "-" + randomHex(4);
}

struct BatchRunner::Impl {
  // Set before the thread starts, then owned by it.
  std::unique_ptr<log::ResultsDb> db;
  std::unique_ptr<BatchStore> store;
  RunnerOptions options;
  ProgressCallback callback;
  std::string batch_id;
  std::vector<RunSpec> todo;
  std::unique_ptr<AxisStop> axis;  ///< over every run of the batch (finished ones fed in)

  int wake_read = -1;
  int wake_write = -1;
  std::atomic<int> cancel_requests{0};
  std::atomic<bool> finished{false};
  std::thread thread;
  bool launched = false;

  mutable std::mutex mutex;  // guards progress and result
  BatchProgress progress;
  BatchResult result;

  // Runner-thread state.
  std::list<RunChild> children;
  Stopwatch clock;
  std::int64_t finished_here = 0;
  bool cancelling = false;
  bool escalated = false;

  Impl() {
    int fds[2];
    DASH_DEMAND(pipe2(fds, O_NONBLOCK | O_CLOEXEC) == 0);
    wake_read = fds[0];
    wake_write = fds[1];
  }
  ~Impl() {
    close(wake_read);
    close(wake_write);
  }

  void count(log::RunStatus status, std::int64_t n = 1) {
    switch (status) {
      case log::RunStatus::Solved:
        progress.solved += n;
        break;
      case log::RunStatus::Timeout:
        progress.timeouts += n;
        progress.failed += n;
        break;
      case log::RunStatus::Infeasible:
        progress.failed += n;
        break;
      case log::RunStatus::Crashed:
        progress.crashed += n;
        progress.failed += n;
        break;
      case log::RunStatus::Cancelled:
        progress.cancelled += n;
        return;
      case log::RunStatus::Running:
        return;
    }
    progress.done += n;
  }

  void publish(std::optional<FinishedRun> finished_run = std::nullopt) {
    BatchProgress copy;
    {
      std::lock_guard lock(mutex);
      progress.running = static_cast<std::int64_t>(children.size());
      progress.remaining = progress.total - progress.done;
      progress.elapsed = clock.seconds();
      progress.cancelling = cancelling;
      const auto to_run = static_cast<std::int64_t>(todo.size());
      progress.eta = finished_here > 0 && !cancelling
                         ? progress.elapsed / static_cast<double>(finished_here) *
                               static_cast<double>(std::max<std::int64_t>(0, to_run - finished_here))
                         : -1.0;
      progress.finished = std::move(finished_run);
      progress.active.clear();
      const Clock::time_point now = Clock::now();
      for (const RunChild& c : children)
        progress.active.push_back({c.run.key, c.uuid, Seconds(now - c.spawned).count(), c.work, c.phase});
      copy = progress;
      progress.finished.reset();
    }
    if (callback) callback(copy);
  }

  /// Batches of this file left 'running' by a runner that is gone become 'interrupted' (so that
  /// readers of dash_batches, such as the server, see the truth without knowing about heartbeats).
  void markDeadBatches() {
    for (const log::BatchRecord& b : db->listBatches()) {
      if (b.status != "running") continue;
      const auto runner = store->runner(b.id);
      if (!runner || !runner->alive()) db->setBatchStatus(b.id, "interrupted");
    }
  }

  /// The store's writes need the ResultsDb's batched transaction closed first.
  BatchStore& storeForWrite() {
    db->flush();
    return *store;
  }

  void launch() {
    {
      std::lock_guard lock(mutex);
      progress.batch_id = batch_id;
      progress.total = static_cast<std::int64_t>(todo.size()) + progress.skipped;
    }
    cancel_requests.store(0);
    drainPipe(wake_read);
    storeForWrite().setRunner(batch_id, RunnerInfo{.pid = getpid(),
                                                   .host = hostName(),
                                                   .started = utcNow("%Y-%m-%dT%H:%M:%SZ"),
                                                   .heartbeat = 0.0,
                                                   .workers = options.workers});
    db->setBatchStatus(batch_id, "running");
    launched = true;
    clock.restart();
    thread = std::thread([this] { threadMain(); });
  }

  void threadMain() {
    std::string status = "finished";
    std::string error;
    try {
      loop();
      status = cancelling ? "cancelled" : "finished";
    } catch (const std::exception& e) {
      status = "interrupted";
      error = e.what();
      killAll();
    }
    try {
      db->flush();
      db->setBatchStatus(batch_id, status);
      storeForWrite().clearRunner(batch_id);
    } catch (const std::exception& e) {
      if (error.empty()) error = e.what();
      status = "interrupted";
    }
    publish();
    {
      std::lock_guard lock(mutex);
      result.batch_id = batch_id;
      result.status = status;
      result.error = error;
      result.progress = progress;
    }
    finished.store(true);
  }

  /// After a fatal runner error: kill and reap every child (their rows stay 'running': a resume re-runs them).
  void killAll() noexcept {
    for (RunChild& c : children) {
      if (c.pid > 0) {
        kill(c.pid, SIGKILL);
        int st = 0;
        waitpid(c.pid, &st, 0);
      }
      if (c.msg_fd >= 0) close(c.msg_fd);
      if (c.err_fd >= 0) close(c.err_fd);
    }
    children.clear();
  }

  /// The next run of `waiting` that may start (its index there), marking the ones the axis stop rule
  /// skips on the way; none when every one left waits for a smaller size still running.
  std::optional<std::size_t> nextRun(std::vector<std::size_t>& waiting) {
    for (std::size_t i = 0; i < waiting.size();) {
      const RunSpec& run = todo[waiting[i]];
      const AxisStop::Decision d = axis->decide(run);
      if (d.verdict == AxisStop::Verdict::kRun) return i;
      if (d.verdict == AxisStop::Verdict::kWait) {
        ++i;
        continue;
      }
      storeForWrite().markSkipped(batch_id, run.key, d.reason);
      axis->finished(run, false);
      ++finished_here;
      {
        std::lock_guard lock(mutex);
        ++progress.axis_skipped;
        ++progress.done;
      }
      waiting.erase(waiting.begin() + static_cast<std::ptrdiff_t>(i));
      publish();
    }
    // Nothing runnable and nothing running: cannot happen (the smallest size never waits), but
    // never deadlock on it.
    if (!waiting.empty() && children.empty()) return 0;
    return std::nullopt;
  }

  void loop() {
    std::vector<std::size_t> waiting(todo.size());
    for (std::size_t i = 0; i < todo.size(); ++i) waiting[i] = i;
    auto last_heartbeat = Clock::now();
    auto last_flush = Clock::now();
    auto last_tick = Clock::now();
    publish();
    while (true) {
      const int requests = cancel_requests.load();
      if (requests > 0 && !cancelling) {
        cancelling = true;
        for (RunChild& c : children) stopChild(c, StopReason::kCancel, options.kill_grace);
        publish();
      }
      if (requests > 1 && !escalated) {
        escalated = true;
        for (RunChild& c : children) killChild(c);
      }
      bool spawned = false;
      while (!cancelling && children.size() < static_cast<std::size_t>(std::max(1, options.workers))) {
        const std::optional<std::size_t> pick = nextRun(waiting);
        if (!pick) break;
        const std::size_t index = waiting[*pick];
        waiting.erase(waiting.begin() + static_cast<std::ptrdiff_t>(*pick));
        spawn(todo[index]);
        spawned = true;
      }
      if (spawned) publish();
      if (children.empty() && (cancelling || waiting.empty())) break;

      waitForChildren(children, wake_read, kPollInterval,
                      [this](RunChild& c, const proto::Frame& frame) { handleFrame(c, frame); });

      const auto now = Clock::now();
      for (RunChild& c : children) {
        if (c.pid <= 0) continue;
        if (!c.term_sent && now >= c.term_at) {
          stopChild(c, StopReason::kTime, options.kill_grace);
        } else if (c.term_sent && now >= c.kill_at) {
          killChild(c);
        }
      }
      for (auto it = children.begin(); it != children.end();) {
        if (it->msg_fd < 0 && it->err_fd < 0) {
          // Out of `children` first, so that the progress it reports no longer counts it as running.
          std::list<RunChild> ended;
          ended.splice(ended.begin(), children, it++);
          finishChild(ended.front());
        } else {
          ++it;
        }
      }
      if (now - last_flush >= kFlushInterval) {
        db->flush();
        last_flush = now;
      }
      if (now - last_heartbeat >= kHeartbeatInterval) {
        storeForWrite().heartbeat(batch_id);
        last_heartbeat = now;
      }
      if (now - last_tick >= kProgressInterval) {
        publish();
        last_tick = now;
      }
    }
  }

  void handleFrame(RunChild& c, const proto::Frame& frame) {
    switch (frame.type) {
      case proto::MessageType::kHello: {
        const proto::Hello hello = proto::decodeHello(frame.payload);
        if (hello.version != proto::kProtocolVersion) {
          throw proto::ProtocolError("the child speaks protocol version " + std::to_string(hello.version) +
                                     ", the runner " + std::to_string(proto::kProtocolVersion));
        }
        break;
      }
      case proto::MessageType::kStarted: {
        const std::string scene = proto::decodeStarted(frame.payload);
        c.started = true;
        if (!c.term_sent) {
          c.term_at = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                         Seconds(c.run.time_limit * kTimeLimitMargin + options.time_slack));
        }
        storeForWrite().setScene(c.uuid, scene);
        break;
      }
      case proto::MessageType::kEvent: {
        const log::Event event = proto::decodeEvent(frame.payload);
        if (const auto* w = std::get_if<log::ProgressEvent>(&event.payload)) c.work = *w;
        // Phases nest; the emitter sends a start again for the phase an inner one's end resumes.
        if (const auto* ph = std::get_if<log::PhaseEvent>(&event.payload)) {
          if (ph->boundary == log::PhaseBoundary::Start) c.phase = ph->phase;
          else if (c.phase == ph->phase) c.phase.reset();
        }
        if (c.recorder) c.recorder->onEvent(event);
        break;
      }
      case proto::MessageType::kResult:
        c.result = proto::decodeResult(frame.payload);
        break;
      case proto::MessageType::kError:
        c.error = proto::decodeError(frame.payload);
        break;
    }
  }

  void spawn(const RunSpec& run) {
    RunChild& c = children.emplace_back();
    c.run = run;
    c.uuid = newUuid();
    c.spawned = Clock::now();
    c.term_at = c.spawned + std::chrono::duration_cast<Clock::duration>(Seconds(
                                options.setup_allowance + run.time_limit * kTimeLimitMargin + options.time_slack));
    // Key -> uuid first, then the row: a key never refers to two rows, and a row is never unreferenced.
    storeForWrite().assignUuid(batch_id, run.key, c.uuid);
    log::RunMetadata meta;
    meta.uuid = c.uuid;
    meta.batch_id = batch_id;
    meta.family = run.family;
    meta.params_json = run.paramsJson();
    meta.seed = run.seed;
    meta.planner = run.planner;
    meta.planner_settings_json = withEffectiveParameters(run.planner, run.settings_json);
    meta.planner_config_name = run.label;
    meta.time_limit = run.time_limit;
    if (run.memory_limit_mb > 0) meta.memory_limit = run.memory_limit_mb;
    db->beginRun(meta);
    c.recorder = db->recorder(c.uuid);

    try {
      const RunProcess process =
          spawnRunProcess(options.executable.empty() ? "/proc/self/exe" : options.executable, run);
      c.pid = process.pid;
      c.msg_fd = process.msg_fd;
      c.err_fd = process.err_fd;
    } catch (const std::system_error& e) {
      c.spawn_error = e.what();  // finished (crashed) by the loop: no descriptors to wait for
    }
  }

  void finishChild(RunChild& c) {
    RunEnd end;
    end.run = &c.run;
    if (c.pid > 0) {
      rusage usage{};
      while (wait4(c.pid, &end.wait_status, 0, &usage) < 0 && errno == EINTR) {
      }
      end.peak_rss_mb = static_cast<double>(usage.ru_maxrss) / 1024.0;  // Linux reports KiB
    }
    end.wall_seconds = Seconds(Clock::now() - c.spawned).count();
    end.result = std::move(c.result);
    end.error = std::move(c.error);
    end.protocol_error = c.protocol_error;
    end.spawn_error = c.spawn_error;
    end.stop = c.stop;
    end.stderr_tail = std::move(c.stderr_tail);
    const log::RunSummary s = summarizeRun(end);
    db->finishRun(c.uuid, s);
    c.recorder.reset();
    ++finished_here;
    if (s.status != log::RunStatus::Cancelled && s.status != log::RunStatus::Running)
      axis->finished(c.run, s.status == log::RunStatus::Solved);
    {
      std::lock_guard lock(mutex);
      count(s.status);
    }
    publish(FinishedRun{.key = c.run.key,
                        .uuid = c.uuid,
                        .status = s.status,
                        .seconds = end.wall_seconds,
                        .error = s.error,
                        .exit_signal = s.exit_signal.value_or(0)});
  }
};

BatchRunner::BatchRunner() : impl_(std::make_unique<Impl>()) {}

BatchRunner::~BatchRunner() {
  if (impl_->thread.joinable()) {
    cancel();
    impl_->thread.join();
  }
}

std::string BatchRunner::start(const BatchSpec& spec, const std::string& db_path, const RunnerOptions& options,
                               ProgressCallback progress) {
  Impl& m = *impl_;
  DASH_THROW_UNLESS(!m.launched, "a BatchRunner runs one batch; make another");
  DASH_THROW_UNLESS(options.workers >= 1, "workers must be at least 1");
  m.options = options;
  m.callback = std::move(progress);
  m.db = std::make_unique<log::ResultsDb>(db_path);
  m.store = std::make_unique<BatchStore>(db_path);
  m.batch_id = options.batch_id.empty() ? newBatchId(spec.name) : options.batch_id;
  for (const auto& b : m.db->listBatches()) {
    DASH_THROW_UNLESS(b.id != m.batch_id, "batch " + m.batch_id + " already exists in " + db_path);
  }
  DASH_THROW_UNLESS(spec.unknown_planners.empty(), "the spec names planners this build does not have");
  m.markDeadBatches();
  m.todo = expandRuns(spec);
  m.axis = std::make_unique<AxisStop>(m.todo);
  m.progress.name = spec.name;
  m.db->putBatch(log::BatchRecord{.id = m.batch_id, .name = spec.name, .spec_json = spec.json, .status = "queued"});
  m.storeForWrite().addRuns(m.batch_id, m.todo);
  m.launch();
  return m.batch_id;
}

std::string BatchRunner::resume(const std::string& batch_id, const std::string& db_path, const RunnerOptions& options,
                                ProgressCallback progress) {
  Impl& m = *impl_;
  DASH_THROW_UNLESS(!m.launched, "a BatchRunner runs one batch; make another");
  DASH_THROW_UNLESS(options.workers >= 1, "workers must be at least 1");
  m.options = options;
  m.callback = std::move(progress);
  m.db = std::make_unique<log::ResultsDb>(db_path);
  m.store = std::make_unique<BatchStore>(db_path);
  m.batch_id = batch_id;
  std::optional<log::BatchRecord> batch;
  for (const auto& b : m.db->listBatches()) {
    if (b.id == batch_id) batch = b;
  }
  DASH_THROW_UNLESS(batch.has_value(), "no batch " + batch_id + " in " + db_path);
  if (batch->status == "running" && !options.force_resume) {
    const auto runner = m.store->runner(batch_id);
    if (runner && runner->alive()) {
      throw InputError("batch " + batch_id + " is still being run by process " + std::to_string(runner->pid) + " on " +
                       runner->host + " (last heartbeat " + formatSeconds(std::max(0.0, runner->age())) +
                       " s ago); stop it first (or use --force if that process is not a runner)");
    }
  }
  m.markDeadBatches();
  const std::vector<StoredRun> stored = m.store->runs(batch_id);
  DASH_THROW_UNLESS(!stored.empty(), "batch " + batch_id +
                                         " has no stored run list (it was not started by "
                                         "`dashbench batch run`)");
  m.progress.name = batch->name;
  std::vector<RunSpec> all;
  for (const StoredRun& r : stored) all.push_back(r.spec);
  m.axis = std::make_unique<AxisStop>(all);
  for (const StoredRun& r : stored) {
    if (r.complete()) {
      ++m.progress.skipped;
      if (!r.skipped.empty()) {
        ++m.progress.axis_skipped;
        ++m.progress.done;
        m.axis->finished(r.spec, false);
        continue;
      }
      m.count(log::parseRunStatus(*r.status));
      m.axis->finished(r.spec, *r.status == "solved");
      continue;
    }
    if (!r.run_uuid.empty()) m.storeForWrite().deleteRun(r.run_uuid);
    m.todo.push_back(r.spec);
  }
  m.storeForWrite().deleteOrphans(batch_id);
  m.launch();
  return batch_id;
}

void BatchRunner::cancel() noexcept {
  impl_->cancel_requests.fetch_add(1);
  const char byte = 1;
  (void)!write(impl_->wake_write, &byte, 1);
}

BatchResult BatchRunner::wait() {
  Impl& m = *impl_;
  if (m.thread.joinable()) m.thread.join();
  std::lock_guard lock(m.mutex);
  return m.result;
}

bool BatchRunner::done() const { return impl_->finished.load(); }

BatchProgress BatchRunner::progress() const {
  std::lock_guard lock(impl_->mutex);
  return impl_->progress;
}

}  // namespace dash::batch
