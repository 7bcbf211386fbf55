#include "server/http/gated_server.h"

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <vector>

#include "engine/core/check.h"
#include "server/http/api_util.h"
#include "server/http/connection_stream.h"
#include "server/http/json_depth.h"

namespace dash::http {

namespace {

using Clock = std::chrono::steady_clock;

constexpr auto kMaxPollWait = std::chrono::milliseconds(1000);
constexpr std::size_t kReadChunk = 16 * 1024;

/// httplib's accept loop runs each task at once: handing a socket to the reader does not block.
class InlineQueue : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

const char* reason(int status) {
  switch (status) {
    case 400:
      return "Bad Request";
    case 408:
      return "Request Timeout";
    case 411:
      return "Length Required";
    case 413:
      return "Payload Too Large";
    case 415:
      return "Unsupported Media Type";
    case 416:
      return "Range Not Satisfiable";
    case 431:
      return "Request Header Fields Too Large";
    default:
      return "Service Unavailable";
  }
}

/// A refusal the reader answers itself, then closes. Best effort: the socket is not waited on.
void refuseAndClose(int fd, int status, const std::string& message) {
  const std::string body = errorJson(message);
  const std::string answer = "HTTP/1.1 " + std::to_string(status) + " " + reason(status) +
                             "\r\nContent-Type: application/json\r\nContent-Length: " + std::to_string(body.size()) +
                             "\r\nX-Content-Type-Options: nosniff\r\nConnection: close\r\n\r\n" + body;
  [[maybe_unused]] const ssize_t sent = ::send(fd, answer.data(), answer.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
  ::shutdown(fd, SHUT_RDWR);
  ::close(fd);
}

void closeQuietly(int fd) {
  ::shutdown(fd, SHUT_RDWR);
  ::close(fd);
}

thread_local int current_client_fd = -1;

}  // namespace

bool currentClientGone() {
  if (current_client_fd < 0) return false;
  pollfd p{.fd = current_client_fd, .events = POLLRDHUP, .revents = 0};
  return ::poll(&p, 1, 0) > 0 && (p.revents & (POLLRDHUP | POLLHUP | POLLERR)) != 0;
}

struct GatedServer::Waiting {
  int fd = -1;
  std::string buffer;
  std::size_t served = 0;  ///< requests answered on this connection so far
  Clock::time_point deadline;
  bool started = false;        ///< the current request's first byte has arrived
  bool continue_sent = false;  ///< answered "100 Continue" for the current request
};

GatedServer::GatedServer(GateOptions options) : options_(options) {
  DASH_THROW_UNLESS(options_.workers >= 1 && options_.max_waiting >= 1, "the gate needs workers and room");
  wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  DASH_THROW_UNLESS(wake_fd_ >= 0, "cannot create the connection gate's eventfd");
  new_task_queue = [] { return new InlineQueue; };
  set_write_timeout(std::chrono::duration_cast<std::chrono::seconds>(options_.write_timeout).count());
  workers_ = std::make_unique<httplib::ThreadPool>(options_.workers);
  reader_ = std::thread([this] { readerLoop(); });
}

GatedServer::~GatedServer() {
  stopGate();
  ::close(wake_fd_);
}

void GatedServer::stopGate() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  wake();
  if (reader_.joinable()) reader_.join();
  workers_->shutdown();
}

bool GatedServer::raiseListenBacklog(int backlog) { return ::listen(svr_sock_, backlog) == 0; }

void GatedServer::wake() {
  const std::uint64_t one = 1;
  [[maybe_unused]] const ssize_t n = ::write(wake_fd_, &one, sizeof(one));
}

bool GatedServer::process_and_close_socket(int sock) {
  // Answers go out in pieces (head, body chunks): without this, Nagle's algorithm holds each
  // piece until the client's delayed ACK (40 ms a request on loopback).
  const int one = 1;
  ::setsockopt(sock, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  admit(sock, "", 0);
  return true;
}

void GatedServer::admit(int fd, std::string buffered, std::size_t served) {
  auto w = std::make_unique<Waiting>();
  w->fd = fd;
  w->buffer = std::move(buffered);
  w->served = served;
  w->started = !w->buffer.empty();
  w->deadline = Clock::now() + (w->started ? options_.request_timeout : options_.idle_timeout);
  {
    std::lock_guard lock(mutex_);
    if (stopping_) {
      closeQuietly(fd);
      return;
    }
    incoming_.push_back(std::move(w));
  }
  wake();
}

bool GatedServer::advance(Waiting& w, bool readable, Clock::time_point now) {
  const HeadLimits& limits = options_.limits;
  HeadCheck head = inspectHead(w.buffer, limits);
  if (readable) {
    // Read what the current request still needs (a pipelined next one stays in the kernel).
    for (;;) {
      const std::size_t need = head.complete ? head.head_bytes + head.body_bytes : limits.max_head_bytes;
      if (head.status != 0 || w.buffer.size() >= need) break;
      const std::size_t old = w.buffer.size();
      w.buffer.resize(old + std::min(kReadChunk, need - old));
      const ssize_t n = ::recv(w.fd, w.buffer.data() + old, w.buffer.size() - old, MSG_DONTWAIT);
      w.buffer.resize(old + static_cast<std::size_t>(std::max<ssize_t>(n, 0)));
      if (n == 0 || (n < 0 && errno != EAGAIN && errno != EINTR)) {
        closeQuietly(w.fd);  // the client went away
        return false;
      }
      if (n < 0) break;
      if (!w.started) {
        w.started = true;
        w.deadline = now + options_.request_timeout;
      }
      head = inspectHead(w.buffer, limits);
    }
  }
  if (head.status != 0) {
    refuseAndClose(w.fd, head.status, head.message);
    return false;
  }
  if (!head.complete) return true;
  const std::size_t need = head.head_bytes + head.body_bytes;
  if (w.buffer.size() < need) {
    if (head.expects_continue && !w.continue_sent) {
      constexpr std::string_view kContinue = "HTTP/1.1 100 Continue\r\n\r\n";
      [[maybe_unused]] const ssize_t n = ::send(w.fd, kContinue.data(), kContinue.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
      w.continue_sent = true;
    }
    return true;
  }
  // A whole request: checks that need the body, then a worker.
  std::string request = w.buffer.substr(0, need);
  std::string rest = w.buffer.substr(need);
  if (jsonTooDeep(std::string_view(request).substr(head.head_bytes))) {
    refuseAndClose(w.fd, 400, "the request body nests deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    return false;
  }
  if (w.continue_sent) {
    // Answered already; httplib would answer it again.
    request = withoutExpect(std::string_view(request).substr(0, head.head_bytes)) + request.substr(head.head_bytes);
  }
  if (in_flight_.load() >= options_.workers + options_.max_queued) {
    refuseAndClose(w.fd, 503, "the server is busy; try again in a moment");
    return false;
  }
  ++in_flight_;
  const std::size_t request_bytes = request.size();
  request += rest;  // pipelined bytes: the stream keeps them for the next request
  const int fd = w.fd;
  const std::size_t served = w.served;
  workers_->enqueue([this, fd, request = std::move(request), request_bytes, served]() mutable {
    serve(fd, std::move(request), request_bytes, served);
  });
  return false;
}

void GatedServer::serve(int fd, std::string request, std::size_t request_bytes, std::size_t served) {
  ConnectionStream stream(fd, std::move(request), request_bytes, options_.idle_timeout, options_.write_timeout);
  bool stopping = false;
  {
    std::lock_guard lock(mutex_);
    stopping = stopping_;
  }
  const bool last = stopping || served + 1 >= options_.max_requests_per_connection;
  bool client_closes = false;
  current_client_fd = fd;
  const bool answered = process_request(stream, last, client_closes, nullptr);
  current_client_fd = -1;
  --in_flight_;
  if (answered && !last && !client_closes) {
    admit(fd, stream.takeBuffered(), served + 1);
  } else {
    closeQuietly(fd);
  }
}

void GatedServer::dropOldest(std::vector<std::unique_ptr<Waiting>>& waiting) const {
  // The connections waiting longest are the slow ones: drop them, keep room for new clients.
  std::size_t bytes = 0;
  for (const auto& w : waiting) bytes += w->buffer.size();
  std::size_t drop = 0;
  while (drop < waiting.size() &&
         (waiting.size() - drop > options_.max_waiting || bytes > options_.max_buffered_bytes)) {
    bytes -= waiting[drop]->buffer.size();
    closeQuietly(waiting[drop]->fd);
    ++drop;
  }
  waiting.erase(waiting.begin(), waiting.begin() + static_cast<std::ptrdiff_t>(drop));
}

void GatedServer::readerLoop() {
  std::vector<std::unique_ptr<Waiting>> waiting;  // oldest first
  std::vector<pollfd> fds;
  for (;;) {
    std::vector<std::unique_ptr<Waiting>> arrived;
    {
      std::lock_guard lock(mutex_);
      if (stopping_) break;
      while (!incoming_.empty()) {
        arrived.push_back(std::move(incoming_.front()));
        incoming_.pop_front();
      }
    }
    const Clock::time_point now = Clock::now();
    for (auto& w : arrived) {
      // A returning connection may hold a whole pipelined request already.
      if (w->buffer.empty() || advance(*w, false, now)) waiting.push_back(std::move(w));
    }
    dropOldest(waiting);

    fds.assign(1, pollfd{.fd = wake_fd_, .events = POLLIN, .revents = 0});
    Clock::time_point next = now + kMaxPollWait;
    for (const auto& w : waiting) {
      fds.push_back(pollfd{.fd = w->fd, .events = POLLIN, .revents = 0});
      next = std::min(next, w->deadline);
    }
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next - now).count() + 1;
    ::poll(fds.data(), fds.size(), static_cast<int>(std::max<long>(wait, 0)));
    if (fds[0].revents != 0) {
      std::uint64_t count = 0;
      [[maybe_unused]] const ssize_t n = ::read(wake_fd_, &count, sizeof(count));
    }

    const Clock::time_point after = Clock::now();
    std::vector<std::unique_ptr<Waiting>> still;
    still.reserve(waiting.size());
    for (std::size_t i = 0; i < waiting.size(); ++i) {
      Waiting& w = *waiting[i];
      const bool readable = (fds[i + 1].revents & (POLLIN | POLLHUP | POLLERR)) != 0;
      if (!advance(w, readable, after)) continue;
      if (after >= w.deadline) {
        if (w.started) {
          refuseAndClose(w.fd, 408, "the request did not arrive in time");
        } else {
          closeQuietly(w.fd);  // an idle kept-alive connection
        }
        continue;
      }
      still.push_back(std::move(waiting[i]));
    }
    waiting.swap(still);
    dropOldest(waiting);
  }
  for (const auto& w : waiting) closeQuietly(w->fd);
  std::lock_guard lock(mutex_);
  for (const auto& w : incoming_) closeQuietly(w->fd);
  incoming_.clear();
}

}  // namespace dash::http
