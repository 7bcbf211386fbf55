#pragma once
// A program run in the background by a test (fork + execve): started, waited for, signalled, and
// never left behind (SIGTERM, then SIGKILL, on destruction).
#include <fcntl.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

extern char** environ;

namespace dash::test {

class ChildProcess {
 public:
  struct Options {
    /// Its stdout and stderr go to this file (created or truncated); empty: this process's own.
    std::string output;
    /// NAME=VALUE entries added to (or replacing those of) this process's environment.
    std::vector<std::string> env;
  };

  /// Starts argv[0] (a path, not looked up on PATH) with `argv`. pid() is -1 when fork failed; a
  /// program that cannot be executed exits with 127.
  explicit ChildProcess(std::vector<std::string> argv, Options options = {}) : output_(std::move(options.output)) {
    // Everything the child needs is built here: between fork and exec a threaded parent's child may
    // only make async-signal-safe calls (no allocation).
    std::vector<char*> args;
    for (std::string& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    std::vector<std::string> env_text;
    for (char** e = environ; *e != nullptr; ++e) {
      const std::string entry = *e;
      const std::string name = entry.substr(0, entry.find('=') + 1);
      bool replaced = false;
      for (const std::string& extra : options.env) replaced = replaced || extra.compare(0, name.size(), name) == 0;
      if (!replaced) env_text.push_back(entry);
    }
    env_text.insert(env_text.end(), options.env.begin(), options.env.end());
    std::vector<char*> envp;
    for (std::string& e : env_text) envp.push_back(e.data());
    envp.push_back(nullptr);
    const int out = output_.empty() ? -1 : ::open(output_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);

    pid_ = ::fork();
    if (pid_ == 0) {
      if (out >= 0) {  // dup2 clears close-on-exec on the copies
        ::dup2(out, 1);
        ::dup2(out, 2);
      }
      ::execve(args[0], args.data(), envp.data());
      ::_exit(127);
    }
    if (out >= 0) ::close(out);
  }
  ~ChildProcess() { stop(); }
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  /// -1 once it has been waited for (its pid is never signalled again), or when fork failed.
  pid_t pid() const { return pid_; }

  /// Waits for it to exit; its exit status: the exit code, or 128 + the signal that ended it (as a
  /// shell writes it). -1 when there is nothing to wait for.
  int wait() {
    if (pid_ <= 0) return -1;
    int status = 0;
    pid_t done = -1;
    do {
      done = ::waitpid(pid_, &status, 0);
    } while (done < 0 && errno == EINTR);
    if (done != pid_) {
      pid_ = -1;
      return -1;
    }
    return reaped(status);
  }
  /// Waits up to `timeout_s` for it to exit; its exit status as wait() gives it, or nullopt if it
  /// is still running.
  std::optional<int> wait(double timeout_s) {
    if (pid_ <= 0) return std::nullopt;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (true) {
      int status = 0;
      if (::waitpid(pid_, &status, WNOHANG) == pid_) return reaped(status);
      if (std::chrono::steady_clock::now() >= end) return std::nullopt;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }
  /// Sends `signal` without waiting; false when it has already been waited for.
  bool kill(int signal = SIGTERM) { return pid_ > 0 && ::kill(pid_, signal) == 0; }
  /// SIGTERM, up to `grace_s` to exit, then SIGKILL; its exit status as wait() gives it.
  int stop(double grace_s = 5.0) {
    if (pid_ <= 0) return -1;
    kill(SIGTERM);
    if (const std::optional<int> status = wait(grace_s)) return *status;
    kill(SIGKILL);
    return wait();
  }

  /// What it wrote to Options::output so far (empty without one).
  std::string log() const {
    if (output_.empty()) return "";
    std::ifstream in(output_, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

 private:
  int reaped(int status) {
    pid_ = -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
  }

  pid_t pid_ = -1;
  std::string output_;
};

#ifdef DASHBENCH_BINARY
/// The command line `dashbench ARGS...` of the built binary, for ChildProcess.
inline std::vector<std::string> dashbenchCommand(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {DASHBENCH_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}
#endif

}  // namespace dash::test
