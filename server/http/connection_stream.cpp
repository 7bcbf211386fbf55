#include "server/http/connection_stream.h"

#include <arpa/inet.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace dash::http {

namespace {

bool waitFor(int fd, short events, std::chrono::milliseconds timeout) {
  pollfd p{.fd = fd, .events = events, .revents = 0};
  const int n = ::poll(&p, 1, static_cast<int>(timeout.count()));
  return n > 0 && (p.revents & (events | POLLHUP | POLLERR)) != 0;
}

void addressOf(const sockaddr_storage& address, socklen_t length, std::string& ip, int& port) {
  char host[NI_MAXHOST] = {};
  char service[NI_MAXSERV] = {};
  if (::getnameinfo(reinterpret_cast<const sockaddr*>(&address), length, host, sizeof(host), service, sizeof(service),
                    NI_NUMERICHOST | NI_NUMERICSERV) == 0) {
    ip = host;
    port = std::atoi(service);
  }
}

}  // namespace

ConnectionStream::ConnectionStream(int fd, std::string buffered, std::size_t request_bytes,
                                   std::chrono::milliseconds read_timeout, std::chrono::milliseconds write_timeout)
    : fd_(fd),
      buffered_(std::move(buffered)),
      request_end_(std::min(request_bytes, buffered_.size())),
      read_timeout_(read_timeout),
      write_timeout_(write_timeout) {}

// The gate hands over whole requests (head and Content-Length body): nothing past the request's end
// is read. A request httplib expects a body for but that has no length (a DELETE without one) reads
// as an empty body here, where httplib's own stream read until the client closed, with no limit.
bool ConnectionStream::is_readable() const { return true; }

bool ConnectionStream::is_writable() const {
  if (!waitFor(fd_, POLLOUT, write_timeout_)) return false;
  // As httplib's own stream: a peer that closed (readable, nothing to read) is gone. This is how an
  // event stream notices a closed tab between two messages.
  pollfd p{.fd = fd_, .events = POLLIN, .revents = 0};
  if (::poll(&p, 1, 0) <= 0) return true;
  char byte = 0;
  return ::recv(fd_, &byte, 1, MSG_PEEK | MSG_DONTWAIT) > 0;
}

ssize_t ConnectionStream::read(char* ptr, std::size_t size) {
  if (offset_ >= request_end_) return 0;  // the end of this request
  const std::size_t n = std::min(size, request_end_ - offset_);
  std::memcpy(ptr, buffered_.data() + offset_, n);
  offset_ += n;
  return static_cast<ssize_t>(n);
}

ssize_t ConnectionStream::write(const char* ptr, std::size_t size) {
  ssize_t n = -1;
  do {
    if (!is_writable()) return -1;
    n = ::send(fd_, ptr, size, MSG_NOSIGNAL | MSG_DONTWAIT);
  } while (n < 0 && (errno == EAGAIN || errno == EINTR));
  return n;
}

void ConnectionStream::get_remote_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage address{};
  socklen_t length = sizeof(address);
  if (::getpeername(fd_, reinterpret_cast<sockaddr*>(&address), &length) == 0) addressOf(address, length, ip, port);
}

void ConnectionStream::get_local_ip_and_port(std::string& ip, int& port) const {
  sockaddr_storage address{};
  socklen_t length = sizeof(address);
  if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&address), &length) == 0) addressOf(address, length, ip, port);
}

int ConnectionStream::socket() const { return fd_; }

std::string ConnectionStream::takeBuffered() {
  std::string rest = buffered_.substr(std::max(offset_, request_end_));
  buffered_.clear();
  offset_ = 0;
  return rest;
}

}  // namespace dash::http
