#include "server/batch/run_child.h"

#include <poll.h>
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>
#include <vector>

namespace dash::batch {
namespace {

using Seconds = std::chrono::duration<double>;
using std::chrono::milliseconds;

constexpr int kReadsPerWakeup = 16;             ///< per pipe, so that one chatty child cannot starve the rest
constexpr std::size_t kStderrTailBytes = 4000;  ///< kept per child for the error text of a crash

void readStderr(RunChild& c) {
  char buf[4096];
  for (int i = 0; i < kReadsPerWakeup; ++i) {
    const ssize_t n = read(c.err_fd, buf, sizeof buf);
    if (n > 0) {
      c.stderr_tail.append(buf, static_cast<std::size_t>(n));
      if (c.stderr_tail.size() > kStderrTailBytes) c.stderr_tail.erase(0, c.stderr_tail.size() - kStderrTailBytes);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;
    close(c.err_fd);
    c.err_fd = -1;
    return;
  }
}

void readMessages(RunChild& c, const FrameHandler& handle) {
  char buf[65536];
  for (int i = 0; i < kReadsPerWakeup; ++i) {
    const ssize_t n = read(c.msg_fd, buf, sizeof buf);
    if (n > 0) {
      if (!c.protocol_error.empty()) continue;  // drain, ignore
      c.decoder.feed(buf, static_cast<std::size_t>(n));
      try {
        proto::Frame frame;
        while (c.decoder.next(frame)) handle(c, frame);
      } catch (const proto::ProtocolError& e) {
        c.protocol_error = e.what();
        killChild(c);
      }
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) return;
    close(c.msg_fd);
    c.msg_fd = -1;
    return;
  }
}

}  // namespace

void stopChild(RunChild& c, StopReason why, double grace_seconds) {
  if (c.pid <= 0 || c.term_sent) return;
  kill(c.pid, SIGTERM);
  c.term_sent = true;
  c.stop = why;
  c.kill_at = Clock::now() + std::chrono::duration_cast<Clock::duration>(Seconds(grace_seconds));
}

void killChild(RunChild& c) {
  if (c.pid <= 0 || c.kill_sent) return;
  kill(c.pid, SIGKILL);
  c.kill_sent = true;
}

void drainPipe(int fd) {
  char drain[64];
  while (read(fd, drain, sizeof drain) > 0) {
  }
}

void waitForChildren(std::list<RunChild>& children, int wake_fd, milliseconds longest, const FrameHandler& handle) {
  std::vector<pollfd> fds;
  std::vector<std::pair<RunChild*, bool>> owners;  // (child, is its stderr)
  fds.push_back({wake_fd, POLLIN, 0});
  owners.emplace_back(nullptr, false);
  auto timeout = longest;
  const auto now = Clock::now();
  for (RunChild& c : children) {
    if (c.msg_fd >= 0) {
      fds.push_back({c.msg_fd, POLLIN, 0});
      owners.emplace_back(&c, false);
    }
    if (c.err_fd >= 0) {
      fds.push_back({c.err_fd, POLLIN, 0});
      owners.emplace_back(&c, true);
    }
    if (c.pid > 0 && !c.kill_sent) {
      const auto due = c.term_sent ? c.kill_at : c.term_at;
      const auto left = std::chrono::ceil<milliseconds>(due - now);
      timeout = std::clamp(left, milliseconds(0), timeout);
    }
  }
  const int n = poll(fds.data(), fds.size(), static_cast<int>(timeout.count()));
  if (n < 0) {
    if (errno == EINTR) return;
    throw std::runtime_error(std::string("poll failed: ") + std::strerror(errno));
  }
  if (fds[0].revents != 0) drainPipe(wake_fd);
  for (std::size_t i = 1; i < fds.size(); ++i) {
    if (fds[i].revents == 0) continue;
    RunChild& c = *owners[i].first;
    if (owners[i].second) {
      readStderr(c);
    } else {
      readMessages(c, handle);
    }
  }
}

}  // namespace dash::batch
