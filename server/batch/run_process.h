#pragma once
// One run's process, seen from the batch runner: starting it (fork + exec of `dashbench run-one`
// with its limits) and turning how it ended into the run's database outcome.
#include <sys/types.h>

#include <optional>
#include <string>
#include <string_view>

#include "engine/log/results_db.h"
#include "server/batch/batch_spec.h"
#include "server/batch/run_protocol.h"

namespace dash::batch {

/// A started run process: its pid and the (non-blocking, close-on-exec) read ends of its message
/// pipe (the child's descriptor 3) and its stderr.
struct RunProcess {
  pid_t pid = -1;
  int msg_fd = -1;
  int err_fd = -1;
};

/// Forks and execs `executable run-one --fd 3 --run JSON`. In the child, before exec: a process group
/// of its own (Ctrl-C at the terminal reaches only the runner, which stops the children cleanly),
/// SIGKILL when the forking thread dies (PR_SET_PDEATHSIG: a runner killed with SIGKILL takes its
/// children along), RLIMIT_AS from the run's memory limit, stdin/stdout on /dev/null, every other
/// descriptor closed. Async-signal-safe between fork and exec, so it may be called from a
/// multi-threaded process (the server). Throws std::system_error if a pipe or fork fails.
RunProcess spawnRunProcess(const std::string& executable, const RunSpec& run);

/// How the error of a run stopped by its memory limit begins (stored as crashed; reports count it apart).
inline constexpr std::string_view kOutOfMemoryError = "out of memory";

/// Why the runner signalled a process, if it did.
enum class StopReason { kNone, kTime, kCancel };

/// Everything known about a run once its process has ended and been reaped.
struct RunEnd {
  const RunSpec* run = nullptr;
  std::optional<proto::ChildResult> result;  ///< the child's result frame, if it sent one
  std::optional<proto::ChildError> error;    ///< the child's error frame, if it sent one
  std::string protocol_error;                ///< a malformed message (the runner killed the child)
  std::string spawn_error;                   ///< the process could not be started
  int wait_status = 0;                       ///< from waitpid (unused with spawn_error)
  StopReason stop = StopReason::kNone;
  double wall_seconds = 0.0;  ///< since the process started
  double peak_rss_mb = 0.0;   ///< from the child's rusage; 0 if unknown
  std::string stderr_tail;    ///< the last lines the child wrote to stderr
};

/// The run's outcome for ResultsDb::finishRun:
///   a result         -> its outcome (solved, timeout, infeasible, cancelled) and figures; a run the
///                       runner stopped for time that did not solve is a timeout;
///   killed by signal -> timeout (stopped for time), cancelled (stopped by cancel), otherwise
///                       crashed with the signal as exit_signal and stderr's tail in the error;
///   exited without a result -> crashed (or timeout/cancelled when stopped), with the child's error
///                       frame ("out of memory", scene generation failed, ...) or its exit code.
log::RunSummary summarizeRun(const RunEnd& end);

/// "SIGABRT", or "signal 64".
std::string signalName(int sig);

}  // namespace dash::batch
