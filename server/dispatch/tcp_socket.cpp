#include "server/dispatch/tcp_socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "engine/core/check.h"

namespace dash::dispatch {

namespace {

void setNoDelay(int fd) {
  int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

bool resolve(const std::string& host, int port, sockaddr_in& addr) {
  std::memset(&addr, 0, sizeof addr);
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  const std::string h = host.empty() ? "0.0.0.0" : host;
  if (::inet_pton(AF_INET, h.c_str(), &addr.sin_addr) == 1) return true;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* result = nullptr;
  if (::getaddrinfo(h.c_str(), nullptr, &hints, &result) != 0 || result == nullptr) return false;
  addr.sin_addr = reinterpret_cast<sockaddr_in*>(result->ai_addr)->sin_addr;
  ::freeaddrinfo(result);
  return true;
}

int pollOne(int fd, short events, int timeout_ms) {
  pollfd p{fd, events, 0};
  for (;;) {
    const int r = ::poll(&p, 1, timeout_ms);
    if (r < 0 && errno == EINTR) continue;
    return r;
  }
}

}  // namespace

void Socket::reset() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void Socket::shutdown() {
  if (fd_ >= 0) ::shutdown(fd_, SHUT_RDWR);
}

Socket listenTcp(const std::string& host, int port, int backlog) {
  sockaddr_in addr{};
  DASH_THROW_UNLESS(resolve(host, port, addr), "cannot resolve '" + host + "'");
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  DASH_THROW_UNLESS(s.valid(), std::string("socket(): ") + std::strerror(errno));
  int one = 1;
  ::setsockopt(s.fd(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(s.fd(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    throw InputError("cannot listen on " + host + ":" + std::to_string(port) + ": " + std::strerror(errno));
  }
  DASH_THROW_UNLESS(::listen(s.fd(), backlog) == 0, std::string("listen(): ") + std::strerror(errno));
  return s;
}

int boundPort(const Socket& socket) {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  if (::getsockname(socket.fd(), reinterpret_cast<sockaddr*>(&addr), &len) != 0) return -1;
  return ntohs(addr.sin_port);
}

Socket acceptTcp(const Socket& listener, int timeout_ms) {
  if (pollOne(listener.fd(), POLLIN, timeout_ms) <= 0) return Socket();
  Socket s(::accept4(listener.fd(), nullptr, nullptr, SOCK_CLOEXEC));
  if (s.valid()) setNoDelay(s.fd());
  return s;
}

Socket connectTcp(const std::string& host, int port, int timeout_ms) {
  sockaddr_in addr{};
  if (!resolve(host, port, addr)) return Socket();
  Socket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
  if (!s.valid()) return Socket();
  const int r = ::connect(s.fd(), reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  if (r != 0) {
    if (errno != EINPROGRESS) return Socket();
    if (pollOne(s.fd(), POLLOUT, timeout_ms) <= 0) return Socket();
    int error = 0;
    socklen_t len = sizeof error;
    if (::getsockopt(s.fd(), SOL_SOCKET, SO_ERROR, &error, &len) != 0 || error != 0) return Socket();
  }
  // Back to blocking mode: reads and writes below poll for their own timeouts.
  const int flags = ::fcntl(s.fd(), F_GETFL, 0);
  ::fcntl(s.fd(), F_SETFL, flags & ~O_NONBLOCK);
  setNoDelay(s.fd());
  return s;
}

std::string localAddress(const Socket& socket) {
  sockaddr_in addr{};
  socklen_t len = sizeof addr;
  if (::getsockname(socket.fd(), reinterpret_cast<sockaddr*>(&addr), &len) != 0) return "";
  char text[INET_ADDRSTRLEN] = {0};
  ::inet_ntop(AF_INET, &addr.sin_addr, text, sizeof text);
  return text;
}

bool waitReadable(int fd, int timeout_ms) { return pollOne(fd, POLLIN, timeout_ms) > 0; }

IoResult readExact(int fd, void* data, std::size_t n, int timeout_ms) {
  auto* out = static_cast<std::uint8_t*>(data);
  std::size_t got = 0;
  while (got < n) {
    const int r = pollOne(fd, POLLIN, timeout_ms);
    if (r == 0) return IoResult::kTimeout;
    if (r < 0) return IoResult::kClosed;
    const ssize_t k = ::recv(fd, out + got, n - got, 0);
    if (k < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (k <= 0) return IoResult::kClosed;
    got += static_cast<std::size_t>(k);
  }
  return IoResult::kOk;
}

IoResult readLine(int fd, std::string& line, int timeout_ms, std::size_t max_len) {
  line.clear();
  for (;;) {
    char c = 0;
    const IoResult r = readExact(fd, &c, 1, timeout_ms);
    if (r != IoResult::kOk) return r;
    if (c == '\n') break;
    line.push_back(c);
    if (line.size() > max_len) return IoResult::kClosed;
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return IoResult::kOk;
}

bool writeAll(int fd, const void* data, std::size_t n) {
  const auto* in = static_cast<const std::uint8_t*>(data);
  std::size_t sent = 0;
  while (sent < n) {
    const ssize_t k = ::send(fd, in + sent, n - sent, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    sent += static_cast<std::size_t>(k);
  }
  return true;
}

void putInt32(std::uint8_t* out, std::int32_t value) {
  const auto u = static_cast<std::uint32_t>(value);
  out[0] = static_cast<std::uint8_t>(u >> 24);
  out[1] = static_cast<std::uint8_t>(u >> 16);
  out[2] = static_cast<std::uint8_t>(u >> 8);
  out[3] = static_cast<std::uint8_t>(u);
}

std::int32_t getInt32(const std::uint8_t* in) {
  const std::uint32_t u = (static_cast<std::uint32_t>(in[0]) << 24) | (static_cast<std::uint32_t>(in[1]) << 16) |
                          (static_cast<std::uint32_t>(in[2]) << 8) | static_cast<std::uint32_t>(in[3]);
  return static_cast<std::int32_t>(u);
}

void putDouble(std::uint8_t* out, double value) {
  std::uint64_t u = 0;
  std::memcpy(&u, &value, sizeof u);
  for (int i = 7; i >= 0; --i) {
    out[7 - i] = static_cast<std::uint8_t>(u >> (8 * i));
  }
}

double getDouble(const std::uint8_t* in) {
  std::uint64_t u = 0;
  for (int i = 0; i < 8; ++i) u = (u << 8) | in[i];
  double value = 0.0;
  std::memcpy(&value, &u, sizeof value);
  return value;
}

}  // namespace dash::dispatch
