#include "server/batch/run_one.h"

#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <mutex>
#include <new>
#include <stop_token>
#include <thread>

#include "engine/core/stopwatch.h"
#include "engine/log/results_db.h"
#include "engine/plan/plan_json.h"
#include "engine/planners/planner.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "server/batch/run_protocol.h"

namespace dash::batch {
namespace {

std::atomic<bool> g_stop{false};
extern "C" void onStopSignal(int) { g_stop.store(true); }

class PipeBroken : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Buffers frames and writes them to the parent's pipe: at 64 KiB, at an explicit flush, and every
/// 20 ms from a flusher thread (so a crash loses at most that much, and the parent sees events live).
class PipeWriter {
 public:
  explicit PipeWriter(int fd) : fd_(fd) {}

  template <class F>
  void append(F&& encode, bool flush_now) {
    std::lock_guard lock(mutex_);
    encode(buffer_);
    if (flush_now || buffer_.size() >= (64u << 10)) flushLocked();
  }
  void flush() {
    std::lock_guard lock(mutex_);
    flushLocked();
  }

 private:
  void flushLocked() {
    std::size_t done = 0;
    while (done < buffer_.size()) {
      const ssize_t n = ::write(fd_, buffer_.data() + done, buffer_.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) throw PipeBroken("the batch runner's pipe is closed");
      done += static_cast<std::size_t>(n);
    }
    buffer_.clear();
  }

  int fd_;
  std::mutex mutex_;
  std::string buffer_;
};

/// Flushes `writer` every 20 ms until destroyed.
class Flusher {
 public:
  explicit Flusher(PipeWriter& writer)
      : thread_([&writer](std::stop_token stop) {
          while (!stop.stop_requested()) {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            try {
              writer.flush();
            } catch (const PipeBroken&) {
              _exit(kChildExitPipe);
            }
          }
        }) {}

 private:
  std::jthread thread_;
};

/// Forwards the planner's events into the pipe. onEvent never throws into the planner: a broken
/// pipe (the parent is gone) stops the process, which nobody is listening to any more.
class PipeSink final : public log::EventSink {
 public:
  explicit PipeSink(PipeWriter& writer) : writer_(writer) {}
  void onEvent(const log::Event& event) override {
    try {
      writer_.append([&](std::string& out) { proto::appendEvent(out, event); }, false);
    } catch (const PipeBroken&) {
      _exit(kChildExitPipe);
    }
  }

 private:
  PipeWriter& writer_;
};

}  // namespace

int runOneChild(const RunSpec& run, int fd) {
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGINT, &sa, nullptr);

  PipeWriter writer(fd);
  auto sendError = [&](const std::string& kind, const std::string& message, int code) {
    try {
      writer.append([&](std::string& out) { proto::appendError(out, {kind, message}); }, true);
    } catch (const PipeBroken&) {
      return kChildExitPipe;
    }
    return code;
  };
  try {
    writer.append([&](std::string& out) { proto::appendHello(out, static_cast<std::int64_t>(getpid())); }, true);
    const Scene scene = generateScenario(run.family, ScenarioParams(run.params), run.seed, RobotLibrary::loadDefault());
    auto planner = makePlanner(run.planner);
    PlannerSettings settings;
    settings.seed = run.seed;
    settings.time_limit = run.time_limit;
    settings.task_only = run.task_only;
    settings.test_fault = run.test_fault;
    settings.params = plannerParameterSettings(run.settings_json);
    PipeSink sink(writer);
    const Flusher flusher(writer);
    writer.append([&](std::string& out) { proto::appendStarted(out, scene.name); }, true);
    const Deadline deadline(run.time_limit, &g_stop);
    const Stopwatch clock;
    const PlanResult result = planner->solve(scene, settings, deadline, &sink);
    proto::ChildResult out;
    out.solve_seconds = clock.seconds();
    out.outcome = result.outcome;
    out.message = result.message;
    if (result.plan) out.plan_json = planToJson(*result.plan);
    out.task_plan_json = result.task_plan_json;
    out.stats = result.stats;
    out.peak_memory_mb = log::processPeakMemoryMb();
    writer.append([&](std::string& o) { proto::appendResult(o, out); }, true);
    return 0;
  } catch (const PipeBroken&) {
    return kChildExitPipe;
  } catch (const std::bad_alloc&) {
    return sendError("out-of-memory", "out of memory (std::bad_alloc)", kChildExitOutOfMemory);
  } catch (const InputError& e) {
    return sendError("input", e.what(), kChildExitInput);
  } catch (const std::exception& e) {
    return sendError("internal", e.what(), kChildExitInternal);
  }
}

}  // namespace dash::batch
