#pragma once
// Minimal blocking TCP sockets with timeouts (POSIX), for the robot-side protocols (UR External
// Control, RTDE, the Robotiq gripper socket). Writes never raise SIGPIPE; TCP_NODELAY is always on.
#include <cstddef>
#include <cstdint>
#include <string>

namespace dash::dispatch {

enum class IoResult { kOk, kTimeout, kClosed };

/// An owned socket descriptor (move-only).
class Socket {
 public:
  Socket() = default;
  explicit Socket(int fd) : fd_(fd) {}
  ~Socket() { reset(); }
  Socket(Socket&& other) noexcept : fd_(other.release()) {}
  Socket& operator=(Socket&& other) noexcept {
    if (this != &other) {
      reset();
      fd_ = other.release();
    }
    return *this;
  }
  Socket(const Socket&) = delete;
  Socket& operator=(const Socket&) = delete;

  int fd() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  int release() {
    const int fd = fd_;
    fd_ = -1;
    return fd;
  }
  void reset();
  /// Shuts both directions down (wakes a reader blocked in another thread) without closing.
  void shutdown();

 private:
  int fd_ = -1;
};

/// Listens on host:port (port 0 = any free port). Throws InputError when it cannot bind.
Socket listenTcp(const std::string& host, int port, int backlog = 4);
/// The port a listening socket is bound to.
int boundPort(const Socket& socket);
/// Waits up to timeout_ms for a connection; an invalid Socket on timeout.
Socket acceptTcp(const Socket& listener, int timeout_ms);
/// Connects with a timeout; an invalid Socket on failure.
Socket connectTcp(const std::string& host, int port, int timeout_ms);
/// The local IPv4 address of a connected socket ("192.168.1.5").
std::string localAddress(const Socket& socket);

/// Reads exactly n bytes, waiting at most timeout_ms for each piece (timeout_ms < 0: forever).
IoResult readExact(int fd, void* data, std::size_t n, int timeout_ms);
/// Reads one line without its "\n" (and "\r"), at most max_len bytes.
IoResult readLine(int fd, std::string& line, int timeout_ms, std::size_t max_len = 4096);
/// Writes everything; false if the peer is gone.
bool writeAll(int fd, const void* data, std::size_t n);
/// Whether the socket has bytes to read (or is closed) within timeout_ms.
bool waitReadable(int fd, int timeout_ms);

/// Big-endian (network order) encoding of int32 and double.
void putInt32(std::uint8_t* out, std::int32_t value);
std::int32_t getInt32(const std::uint8_t* in);
void putDouble(std::uint8_t* out, double value);
double getDouble(const std::uint8_t* in);

}  // namespace dash::dispatch
