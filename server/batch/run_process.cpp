#include "server/batch/run_process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <system_error>
#include <vector>

#include "server/batch/run_one.h"

namespace dash::batch {
namespace {

/// The run process's descriptors: the message pipe is 3, as `--fd 3` says.
constexpr int kChildMessageFd = 3;

/// Moves `fd` to a descriptor >= 10 (close-on-exec), so that the child's dup2 onto 0..3 cannot
/// clobber another source descriptor.
int highFd(int fd) {
  if (fd < 0) return fd;
  const int moved = fcntl(fd, F_DUPFD_CLOEXEC, 10);
  if (moved < 0) return fd;
  close(fd);
  return moved;
}

void setNonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) | O_NONBLOCK); }

/// "SIGABRT (Aborted)".
std::string describeSignal(int sig) {
  const char* text = strsignal(sig);
  return signalName(sig) + (text != nullptr ? std::string(" (") + text + ")" : "");
}

std::string formatNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

log::RunStatus statusOf(PlanOutcome outcome) {
  switch (outcome) {
    case PlanOutcome::kSolved:
      return log::RunStatus::Solved;
    case PlanOutcome::kTimeout:
      return log::RunStatus::Timeout;
    case PlanOutcome::kInfeasible:
      return log::RunStatus::Infeasible;
    case PlanOutcome::kCancelled:
      return log::RunStatus::Cancelled;
  }
  return log::RunStatus::Crashed;
}

std::string stderrSuffix(const std::string& stderr_tail) {
  std::string tail = stderr_tail;
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == ' ')) tail.pop_back();
  if (tail.size() > 1500) tail = "..." + tail.substr(tail.size() - 1500);
  return tail.empty() ? "" : "; stderr: " + tail;
}

/// The outcome and figures of a run whose process sent its result.
void fromResult(const RunEnd& end, log::RunSummary& s) {
  const proto::ChildResult& r = *end.result;
  const PlanStats& st = r.stats;
  s.status = statusOf(r.outcome);
  if (end.stop == StopReason::kTime && s.status != log::RunStatus::Solved) s.status = log::RunStatus::Timeout;
  // One phase accounting for both planners (docs/planners.md "Phases"): total = sum of the phases.
  s.total_time = log::phaseSum(st.phase_seconds);
  s.wall_time = st.wall_seconds;
  s.phase_accounting = 2;
  s.phase_seconds = st.phase_seconds;
  const RepresentationCounts& z = st.sizes;
  const std::size_t vertices[] = {z.task_vertices, z.task_extended_vertices, z.motion_vertices,
                                  z.motion_extended_vertices};
  const std::size_t hyperarcs[] = {z.task_hyperarcs, z.task_extended_hyperarcs, z.motion_hyperarcs,
                                   z.motion_extended_hyperarcs};
  log::RepresentationSizes sizes;
  for (int i = 0; i < log::kLayerCount; ++i) {
    sizes.vertices[i] = static_cast<std::int64_t>(vertices[i]);
    sizes.hyperarcs[i] = static_cast<std::int64_t>(hyperarcs[i]);
  }
  s.sizes = sizes;
  s.iterations = st.iterations;
  s.task_space_expansions = st.task_space_expansions;
  s.collision_checks_eager = st.collision_checks_eager;
  s.collision_checks_lazy = st.collision_checks_lazy;
  if (r.peak_memory_mb > 0) s.peak_memory_mb = std::max(s.peak_memory_mb.value_or(0.0), r.peak_memory_mb);
  if (s.status == log::RunStatus::Solved) {
    if (!r.plan_json.empty()) {
      s.plan_json = r.plan_json;
      s.makespan = st.makespan;
      s.path_length = st.path_length;
    }
    return;
  }
  s.error = r.message;
  if (end.stop == StopReason::kTime) {
    s.error = "stopped at the time limit of " + formatNumber(end.run->time_limit) + " s; " + s.error;
  }
}

/// The outcome of a run whose process ended without a result.
void withoutResult(const RunEnd& end, log::RunSummary& s) {
  s.total_time = end.wall_seconds;
  s.wall_time = end.wall_seconds;
  if (!end.spawn_error.empty()) {
    s.status = log::RunStatus::Crashed;
    s.error = "could not start the run's process: " + end.spawn_error;
    return;
  }
  if (WIFSIGNALED(end.wait_status)) {
    const int sig = WTERMSIG(end.wait_status);
    if (end.stop == StopReason::kTime) {
      s.status = log::RunStatus::Timeout;
      s.error = "killed with " + signalName(sig) + " after running past its time limit of " +
                formatNumber(end.run->time_limit) + " s" + (sig == SIGKILL ? " (it ignored SIGTERM)" : "");
    } else if (end.stop == StopReason::kCancel) {
      s.status = log::RunStatus::Cancelled;
      s.error = "cancelled (killed with " + signalName(sig) + ")";
    } else {
      s.status = log::RunStatus::Crashed;
      s.exit_signal = sig;
      s.error = "killed by " + describeSignal(sig) + stderrSuffix(end.stderr_tail);
    }
    return;
  }
  const int code = WIFEXITED(end.wait_status) ? WEXITSTATUS(end.wait_status) : -1;
  s.status = end.stop == StopReason::kTime     ? log::RunStatus::Timeout
             : end.stop == StopReason::kCancel ? log::RunStatus::Cancelled
                                               : log::RunStatus::Crashed;
  if (end.error && end.error->kind == "out-of-memory") {
    s.status = log::RunStatus::Crashed;
    s.error = std::string(kOutOfMemoryError) + " (memory limit " + formatNumber(end.run->memory_limit_mb) +
              " MB): " + end.error->message;
  } else if (end.error) {
    s.error = (end.error->kind == "input" ? "run setup failed: " : "run failed: ") + end.error->message;
  } else {
    s.error = "exited with code " + std::to_string(code) + " without a result" + stderrSuffix(end.stderr_tail);
  }
}

}  // namespace

std::string signalName(int sig) {
  const char* abbrev = sigabbrev_np(sig);
  return abbrev != nullptr ? std::string("SIG") + abbrev : "signal " + std::to_string(sig);
}

RunProcess spawnRunProcess(const std::string& executable, const RunSpec& run) {
  // Everything the child needs is prepared before fork: after it, only async-signal-safe calls.
  const std::string run_json = run.toJson();
  // One argument may hold at most 32 pages (MAX_ARG_STRLEN); the spec's length limits keep a run's
  // description far below. Past it, exec would fail with nothing but "exec ... failed".
  constexpr std::size_t kMaxArgumentBytes = 32 * 4096 - 1;
  if (run_json.size() > kMaxArgumentBytes) {
    throw std::system_error(E2BIG, std::generic_category(),
                            "the run's description is " + std::to_string(run_json.size()) +
                                " bytes, more than one argument of its process may hold (128 KB)");
  }
  std::vector<std::string> words = {executable, "run-one", "--fd", std::to_string(kChildMessageFd), "--run", run_json};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);

  int msg[2], err[2];
  if (pipe2(msg, O_CLOEXEC) != 0) throw std::system_error(errno, std::generic_category(), "pipe");
  if (pipe2(err, O_CLOEXEC) != 0) {
    const int e = errno;
    close(msg[0]);
    close(msg[1]);
    throw std::system_error(e, std::generic_category(), "pipe");
  }
  for (int* fd : {&msg[0], &msg[1], &err[0], &err[1]}) *fd = highFd(*fd);
  fcntl(msg[0], F_SETPIPE_SZ, 1 << 20);  // best effort: fewer stalls of a chatty planner
  const int devnull = highFd(open("/dev/null", O_RDWR | O_CLOEXEC));
  const auto memory = static_cast<rlim_t>(run.memory_limit_mb * 1024.0 * 1024.0);
  const pid_t parent = getpid();
  static const char kExecFailed[] = "dashbench batch: exec of the run's process failed\n";

  const pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(kChildExitPipe);  // the runner died before prctl
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    signal(SIGPIPE, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    signal(SIGINT, SIG_DFL);
    if (memory > 0) {
      const rlimit limit{memory, memory};
      setrlimit(RLIMIT_AS, &limit);
    }
    if (devnull >= 0) {
      dup2(devnull, 0);
      dup2(devnull, 1);
    }
    dup2(err[1], 2);
    dup2(msg[1], kChildMessageFd);
    close_range(kChildMessageFd + 1, ~0U, 0);
    execv(argv[0], argv.data());
    (void)!write(2, kExecFailed, sizeof kExecFailed - 1);
    _exit(127);
  }
  const int fork_errno = errno;
  close(msg[1]);
  close(err[1]);
  if (devnull >= 0) close(devnull);
  if (pid < 0) {
    close(msg[0]);
    close(err[0]);
    throw std::system_error(fork_errno, std::generic_category(), "fork");
  }
  setNonBlocking(msg[0]);
  setNonBlocking(err[0]);
  return RunProcess{.pid = pid, .msg_fd = msg[0], .err_fd = err[0]};
}

log::RunSummary summarizeRun(const RunEnd& end) {
  log::RunSummary s;
  if (end.peak_rss_mb > 0) s.peak_memory_mb = end.peak_rss_mb;
  if (end.result && end.protocol_error.empty()) {
    fromResult(end, s);
  } else {
    withoutResult(end, s);
  }
  if (!end.protocol_error.empty()) {
    s.status = log::RunStatus::Crashed;
    s.error = "bad message from the run's process: " + end.protocol_error + "; " + s.error;
  }
  return s;
}

}  // namespace dash::batch
