#include "server/batch/slurm_client.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "engine/core/check.h"

extern char** environ;

namespace dash::batch {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

bool allDigits(const std::string& s) {
  if (s.empty()) return false;
  for (char c : s) {
    if (c < '0' || c > '9') return false;
  }
  return true;
}

std::string describe(const std::vector<std::string>& argv, const CommandResult& r) {
  const std::string msg = trim(r.err.empty() ? r.out : r.err);
  return argv.front() + " failed (exit " + std::to_string(r.exit_code) + ")" + (msg.empty() ? "" : ": " + msg);
}

}  // namespace

const char* toString(SlurmState state) {
  switch (state) {
    case SlurmState::kPending:
      return "pending";
    case SlurmState::kRunning:
      return "running";
    case SlurmState::kCompleted:
      return "completed";
    case SlurmState::kFailed:
      return "failed";
    case SlurmState::kTimeout:
      return "timeout";
    case SlurmState::kCancelled:
      return "cancelled";
    case SlurmState::kUnknown:
      return "unknown";
  }
  return "unknown";
}

SlurmState slurmStateFromName(const std::string& name) {
  for (SlurmState s : {SlurmState::kPending, SlurmState::kRunning, SlurmState::kCompleted, SlurmState::kFailed,
                       SlurmState::kTimeout, SlurmState::kCancelled}) {
    if (name == toString(s)) return s;
  }
  return SlurmState::kUnknown;
}

SlurmState parseSlurmState(const std::string& text) {
  std::string word = trim(text);
  word = word.substr(0, word.find(' '));  // "CANCELLED by 0"
  if (word == "PENDING" || word == "REQUEUED" || word == "REQUEUE_HOLD" || word == "REQUEUE_FED" ||
      word == "RESV_DEL_HOLD" || word == "SPECIAL_EXIT") {
    return SlurmState::kPending;
  }
  if (word == "RUNNING" || word == "CONFIGURING" || word == "COMPLETING" || word == "SUSPENDED" ||
      word == "STAGE_OUT" || word == "SIGNALING" || word == "RESIZING" || word == "STOPPED") {
    return SlurmState::kRunning;
  }
  if (word == "COMPLETED") return SlurmState::kCompleted;
  if (word == "TIMEOUT" || word == "DEADLINE") return SlurmState::kTimeout;
  if (word == "CANCELLED" || word == "REVOKED") return SlurmState::kCancelled;
  if (word == "FAILED" || word == "NODE_FAIL" || word == "OUT_OF_MEMORY" || word == "BOOT_FAIL" ||
      word == "PREEMPTED") {
    return SlurmState::kFailed;
  }
  return SlurmState::kUnknown;
}

bool isFinal(SlurmState state) {
  return state == SlurmState::kCompleted || state == SlurmState::kFailed || state == SlurmState::kTimeout ||
         state == SlurmState::kCancelled;
}

std::string parseSbatchJobId(const std::string& output) {
  std::istringstream lines(output);
  std::string line;
  while (std::getline(lines, line)) {
    const std::string id = trim(line.substr(0, line.find(';')));
    if (allDigits(id)) return id;
  }
  throw InputError("sbatch printed no job id: " + trim(output));
}

std::map<int, SlurmState> parseArrayStates(const std::string& output, const std::string& job_id) {
  std::map<int, SlurmState> states;
  std::istringstream lines(output);
  std::string line;
  const std::string prefix = job_id + "_";
  while (std::getline(lines, line)) {
    const auto bar = line.find('|');
    if (bar == std::string::npos) continue;
    const std::string id = trim(line.substr(0, bar));
    if (id.rfind(prefix, 0) != 0) continue;
    const std::string index = id.substr(prefix.size());
    if (!allDigits(index)) continue;  // "1234_[3-9%2]", "1234_5.batch"
    const std::string rest = line.substr(bar + 1);
    states[std::stoi(index)] = parseSlurmState(rest.substr(0, rest.find('|')));
  }
  return states;
}

CommandResult runCommand(const std::vector<std::string>& argv, double timeout_seconds) {
  DASH_DEMAND(!argv.empty());
  CommandResult result;
  int out_pipe[2];
  int err_pipe[2];
  if (pipe2(out_pipe, O_CLOEXEC) != 0) {
    result.err = std::string("pipe: ") + std::strerror(errno);
    return result;
  }
  if (pipe2(err_pipe, O_CLOEXEC) != 0) {
    result.err = std::string("pipe: ") + std::strerror(errno);
    close(out_pipe[0]);
    close(out_pipe[1]);
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  close(out_pipe[1]);
  close(err_pipe[1]);
  if (rc != 0) {
    close(out_pipe[0]);
    close(err_pipe[0]);
    result.err = argv[0] + ": " + std::strerror(rc);
    return result;
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_seconds);
  int fds[2] = {out_pipe[0], err_pipe[0]};
  std::string* sinks[2] = {&result.out, &result.err};
  bool killed = false;
  while (fds[0] >= 0 || fds[1] >= 0) {
    pollfd p[2];
    int n = 0;
    int which[2];
    for (int i = 0; i < 2; ++i) {
      if (fds[i] < 0) continue;
      p[n] = {fds[i], POLLIN, 0};
      which[n++] = i;
    }
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      kill(pid, SIGKILL);
      killed = true;
      break;
    }
    const int ready = poll(p, static_cast<nfds_t>(n), static_cast<int>(left.count()));
    if (ready < 0 && errno != EINTR) break;
    for (int k = 0; k < n && ready > 0; ++k) {
      if (p[k].revents == 0) continue;
      char buf[4096];
      const ssize_t got = read(fds[which[k]], buf, sizeof buf);
      if (got > 0) {
        sinks[which[k]]->append(buf, static_cast<std::size_t>(got));
      } else if (got == 0 || (errno != EINTR && errno != EAGAIN)) {
        close(fds[which[k]]);
        fds[which[k]] = -1;
      }
    }
  }
  for (int fd : fds) {
    if (fd >= 0) close(fd);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.exit_code = 128 + WTERMSIG(status);
  if (killed) result.err += "\n" + argv[0] + ": killed after " + std::to_string(timeout_seconds) + " s";
  return result;
}

bool onPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  if (path == nullptr) return false;
  std::istringstream dirs(path);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    if (dir.empty()) dir = ".";
    const std::string file = dir + "/" + name;
    struct stat st {};
    if (stat(file.c_str(), &st) == 0 && S_ISREG(st.st_mode) && access(file.c_str(), X_OK) == 0) return true;
  }
  return false;
}

bool SlurmClient::available() { return onPath("sbatch"); }

std::string SlurmClient::submit(const std::string& script_path, const std::vector<std::string>& extra_args) const {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), extra_args.begin(), extra_args.end());
  argv.push_back(script_path);
  const CommandResult r = runCommand(argv);
  if (r.exit_code != 0) throw InputError(describe(argv, r));
  return parseSbatchJobId(r.out);
}

std::optional<std::map<int, SlurmState>> SlurmClient::queue(const std::string& job_id) const {
  const std::vector<std::string> argv = {"squeue", "-h", "-r", "-t", "all", "-j", job_id, "-o", "%i|%T"};
  const CommandResult r = runCommand(argv);
  // A job the controller has forgotten (past MinJobAge) is an error for squeue -j: no states, not a failure.
  if (r.exit_code != 0 && r.err.find("Invalid job id") != std::string::npos) return std::map<int, SlurmState>{};
  if (r.exit_code != 0) return std::nullopt;
  return parseArrayStates(r.out, job_id);
}

std::optional<std::map<int, SlurmState>> SlurmClient::accounting(const std::string& job_id) const {
  if (!onPath("sacct")) return std::nullopt;
  const std::vector<std::string> argv = {"sacct", "-n", "-P", "-X", "-j", job_id, "-o", "JobID,State"};
  const CommandResult r = runCommand(argv);
  if (r.exit_code != 0) return std::nullopt;  // "Slurm accounting storage is disabled"
  return parseArrayStates(r.out, job_id);
}

void SlurmClient::cancel(const std::string& job_id) const {
  const std::vector<std::string> argv = {"scancel", job_id};
  const CommandResult r = runCommand(argv);
  if (r.exit_code != 0) throw InputError(describe(argv, r));
}

}  // namespace dash::batch
