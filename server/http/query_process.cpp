#include "server/http/query_process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <vector>

#include "server/http/api_json.h"

namespace dash::http {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kPollMs = 100;
constexpr std::size_t kMaxErrorAnswerBytes = 1 << 20;  ///< a refusal's message quotes at most the SQL
constexpr const char* kOneCallAdvice = " (one function call that long is stopped with its process)";

/// The answer as the API sends it: {"columns", "rows", "truncated", "max_rows", "max_bytes"}, written
/// row by row, at most `max_bytes` of rows (a row that would pass them is left out, truncated). The
/// server sends this text as it is: it never builds the rows again in its own memory (issue 40).
std::string answerText(const log::SqlRows& rows, std::int64_t max_rows, std::int64_t max_bytes) {
  const auto text = [](const Json& j) { return j.dump(-1, ' ', false, Json::error_handler_t::replace); };
  std::string out = "{\"columns\":" + text(rows.columns) + ",\"rows\":[";
  const std::size_t rows_start = out.size();
  const std::size_t budget = rows_start + static_cast<std::size_t>(std::max<std::int64_t>(max_bytes, 0));
  bool cut = false;
  std::string cell;
  for (const auto& row : rows.rows) {
    const std::size_t row_start = out.size();
    out += out.size() == rows_start ? "[" : ",[";
    for (std::size_t c = 0; c < row.size() && !cut; ++c) {
      // Doubles as numbers (NaN and infinities as null), text with invalid UTF-8 replaced.
      cell = text(toJson(row[c]));
      cut = max_bytes > 0 && out.size() + cell.size() + 2 > budget;
      if (!cut) out += (c == 0 ? "" : ",") + cell;
    }
    if (cut) {
      out.resize(row_start);  // the row that passes the budget is left out whole
      break;
    }
    out += "]";
  }
  const bool truncated = rows.truncated || cut;
  out += "],\"truncated\":" + std::string(truncated ? "true" : "false") + ",\"max_rows\":" + std::to_string(max_rows) +
         ",\"max_bytes\":" + std::to_string(max_bytes) + "}";
  return out;
}

bool writeAll(int fd, const std::string& text) {
  std::size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

int highFd(int fd) {
  if (fd < 0 || fd >= 10) return fd;
  const int high = ::fcntl(fd, F_DUPFD_CLOEXEC, 10);
  ::close(fd);
  return high;
}

struct Child {
  pid_t pid = -1;
  int in = -1;   ///< the child's stdin (we write)
  int out = -1;  ///< the child's stdout (we read)
};

Child spawn(const std::string& executable, const QueryProcessLimits& process, double timeout_seconds) {
  std::vector<std::string> words = {executable.empty() ? std::string("/proc/self/exe") : executable, "query-worker"};
  std::vector<char*> argv;
  for (auto& w : words) argv.push_back(w.data());
  argv.push_back(nullptr);
  int in[2], out[2];
  if (::pipe2(in, O_CLOEXEC) != 0) throw std::runtime_error("cannot create a pipe for the query process");
  if (::pipe2(out, O_CLOEXEC) != 0) {
    ::close(in[0]);
    ::close(in[1]);
    throw std::runtime_error("cannot create a pipe for the query process");
  }
  for (int* fd : {&in[0], &in[1], &out[0], &out[1]}) *fd = highFd(*fd);
  const auto cpu = static_cast<rlim_t>(std::ceil(timeout_seconds));
  const rlimit cpu_limit{cpu, cpu + 1};
  const rlimit as_limit{process.address_space_bytes, process.address_space_bytes};
  const rlimit no_core{0, 0};
  const pid_t pid = ::fork();
  if (pid == 0) {
    // Only async-signal-safe calls from here to exec.
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    signal(SIGPIPE, SIG_DFL);
    signal(SIGXCPU, SIG_DFL);
    setrlimit(RLIMIT_CORE, &no_core);
    setrlimit(RLIMIT_CPU, &cpu_limit);
    setrlimit(RLIMIT_AS, &as_limit);
    dup2(in[0], 0);
    dup2(out[1], 1);
    close_range(3, ~0U, 0);  // no client sockets or database files in the child
    execv(argv[0], argv.data());
    _exit(127);
  }
  const int fork_errno = errno;
  ::close(in[0]);
  ::close(out[1]);
  if (pid < 0) {
    ::close(in[1]);
    ::close(out[0]);
    throw std::runtime_error("cannot start the query process: " + std::string(std::strerror(fork_errno)));
  }
  ::fcntl(in[1], F_SETFL, ::fcntl(in[1], F_GETFL) | O_NONBLOCK);
  ::fcntl(out[0], F_SETFL, ::fcntl(out[0], F_GETFL) | O_NONBLOCK);
  return Child{.pid = pid, .in = in[1], .out = out[0]};
}

/// Writes to a pipe whose reader may be gone, without a SIGPIPE for the process.
ssize_t writeNoSignal(int fd, const char* data, std::size_t size) {
  sigset_t pipe_only, old;
  sigemptyset(&pipe_only);
  sigaddset(&pipe_only, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_only, &old);
  const ssize_t n = ::write(fd, data, size);
  const int saved = errno;
  if (n < 0 && saved == EPIPE) {
    const timespec zero{0, 0};
    sigtimedwait(&pipe_only, nullptr, &zero);  // the SIGPIPE this thread just got
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  errno = saved;
  return n;
}

enum class Stop { None, Time, Cancelled, TooBig };

/// The worker's request: the query and its limits, one JSON object.
std::string requestText(const std::string& db_path, const std::string& sql, const log::QueryLimits& limits,
                        const QueryProcessLimits& process) {
  return Json{{"db", db_path},
              {"sql", sql},
              {"max_rows", limits.max_rows},
              {"timeout_seconds", limits.timeout_seconds},
              {"max_cell_bytes", limits.max_cell_bytes},
              {"max_columns", limits.max_columns},
              {"max_result_bytes", limits.max_result_bytes},
              {"sqlite_heap_bytes", process.sqlite_heap_bytes},
              {"time_limit_advice", limits.time_limit_advice},
              {"private_tables", limits.private_tables},
              {"private_advice", limits.private_advice}}
      .dump(-1, ' ', false, Json::error_handler_t::replace);
}

/// Writes `request` to the child and reads its answer until the child closes its stdout, or until
/// `deadline`, `cancelled` or an answer of more than `max_answer` bytes stops the exchange (said so).
Stop exchange(Child& child, const std::string& request, std::string& answer, Clock::time_point deadline,
              std::size_t max_answer, const std::function<bool()>& cancelled) {
  std::size_t written = 0;
  Stop stop = Stop::None;
  while (child.out >= 0) {
    pollfd fds[2] = {{.fd = child.out, .events = POLLIN, .revents = 0},
                     {.fd = child.in, .events = POLLOUT, .revents = 0}};
    ::poll(fds, child.in >= 0 ? 2 : 1, kPollMs);
    if (child.in >= 0 && fds[1].revents != 0) {
      const ssize_t n = writeNoSignal(child.in, request.data() + written, request.size() - written);
      if (n > 0) written += static_cast<std::size_t>(n);
      if ((n < 0 && errno != EAGAIN && errno != EINTR) || written == request.size()) {
        ::close(child.in);
        child.in = -1;
      }
    }
    if (fds[0].revents != 0) {
      char buffer[64 * 1024];
      const ssize_t n = ::read(child.out, buffer, sizeof buffer);
      if (n > 0) answer.append(buffer, static_cast<std::size_t>(n));
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        ::close(child.out);
        child.out = -1;
        break;
      }
      if (answer.size() > max_answer) stop = Stop::TooBig;
    }
    if (stop == Stop::None && Clock::now() >= deadline) stop = Stop::Time;
    if (stop == Stop::None && cancelled && cancelled()) stop = Stop::Cancelled;
    if (stop != Stop::None) break;
  }
  return stop;
}

/// Kills the child when the exchange was stopped, closes its pipes and reaps it; its wait status.
int reap(Child& child, Stop stop) {
  if (stop != Stop::None) ::kill(child.pid, SIGKILL);
  if (child.in >= 0) ::close(child.in);
  if (child.out >= 0) ::close(child.out);
  int status = 0;
  while (::waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

/// The child's answer when it is rows; otherwise the refusal or error it stands for, thrown.
std::string answerOrThrow(const std::string& answer, int status, Stop stop, const log::QueryLimits& limits) {
  switch (stop) {
    case Stop::Time:
      throw log::timeLimitRefused(limits.timeout_seconds, kOneCallAdvice + limits.time_limit_advice);
    case Stop::Cancelled:
      throw InputError("the query was stopped: the client went away");
    case Stop::TooBig:
      throw InputError("the query's answer is too big");
    case Stop::None:
      break;
  }
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGXCPU || WTERMSIG(status) == SIGKILL)) {
    throw log::timeLimitRefused(limits.timeout_seconds, kOneCallAdvice + limits.time_limit_advice);
  }
  if (answer.rfind("{\"columns\":", 0) == 0 && WIFEXITED(status) && WEXITSTATUS(status) == 0) return answer;
  // A refusal or an error: a small object, parsed.
  const Json j = answer.size() <= kMaxErrorAnswerBytes ? Json::parse(answer, nullptr, false) : Json();
  if (j.is_discarded() || !j.is_object() || !j.contains("error")) {
    if (WIFSIGNALED(status)) {
      throw std::runtime_error("the query process died (signal " + std::to_string(WTERMSIG(status)) + ")");
    }
    throw std::runtime_error("the query process failed (exit status " + std::to_string(WEXITSTATUS(status)) + ")");
  }
  const std::string message = j["error"].get<std::string>();
  const std::string kind = j.value("kind", "input");
  if (kind == "refused") throw log::QueryRefused(static_cast<log::QueryGuard>(j.value("guard", 0)), message);
  if (kind == "input") throw InputError(message);
  throw std::runtime_error(message);
}

}  // namespace

std::string runQueryInChild(const std::string& executable, const std::string& db_path, const std::string& sql,
                            const log::QueryLimits& limits, const std::function<bool()>& cancelled,
                            const QueryProcessLimits& process) {
  const std::string request = requestText(db_path, sql, limits, process);
  Child child = spawn(executable, process, limits.timeout_seconds);
  const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                                           limits.timeout_seconds + process.kill_grace_seconds));
  // The rows are at most max_result_bytes of JSON (answerText); more is a broken child.
  const std::size_t max_answer =
      static_cast<std::size_t>(std::max<std::int64_t>(limits.max_result_bytes, 0)) + process.max_answer_overhead_bytes;
  std::string answer;
  const Stop stop = exchange(child, request, answer, deadline, max_answer, cancelled);
  const int status = reap(child, stop);
  return answerOrThrow(answer, status, stop, limits);
}

int queryWorkerMain(int in_fd, int out_fd) {
  std::string text;
  char buffer[64 * 1024];
  for (;;) {
    const ssize_t n = ::read(in_fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    if (text.size() > (std::size_t{16} << 20)) return 2;
  }
  Json answer;
  try {
    const Json request = Json::parse(text);
    sqlite3_hard_heap_limit64(request.value("sqlite_heap_bytes", std::int64_t{384} << 20));
    const log::QueryLimits limits{.max_rows = request.at("max_rows").get<std::int64_t>(),
                                  .timeout_seconds = request.at("timeout_seconds").get<double>(),
                                  .max_cell_bytes = request.at("max_cell_bytes").get<int>(),
                                  .max_columns = request.at("max_columns").get<int>(),
                                  .max_result_bytes = request.at("max_result_bytes").get<std::int64_t>(),
                                  .time_limit_advice = request.value("time_limit_advice", std::string()),
                                  .private_tables = request.value("private_tables", std::vector<std::string>()),
                                  .private_advice = request.value("private_advice", std::string())};
    const log::SqlRows rows = log::runReadOnlyQuery(request.at("db").get<std::string>(),
                                                    request.at("sql").get<std::string>(), limits);
    return writeAll(out_fd, answerText(rows, limits.max_rows, limits.max_result_bytes)) ? 0 : 1;
  } catch (const log::QueryRefused& e) {
    answer = Json{{"error", e.what()}, {"kind", "refused"}, {"guard", static_cast<int>(e.guard())}};
  } catch (const InputError& e) {
    answer = Json{{"error", e.what()}, {"kind", "input"}};
  } catch (const std::bad_alloc&) {
    answer = Json{{"error", "the query ran out of memory (the query process's limit)"}, {"kind", "input"}};
  } catch (const std::exception& e) {
    answer = Json{{"error", e.what()}, {"kind", "internal"}};
  }
  std::string out;
  try {
    out = answer.dump(-1, ' ', false, Json::error_handler_t::replace);
  } catch (const std::bad_alloc&) {
    out = R"x({"error": "the query ran out of memory (the query process's limit)", "kind": "input"})x";
  }
  return writeAll(out_fd, out) ? 0 : 1;
}

}  // namespace dash::http
