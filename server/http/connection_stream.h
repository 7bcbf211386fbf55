#pragma once
// ConnectionStream: cpp-httplib's Stream over a connected socket, which first hands out the bytes the
// connection gate already read (the request head and its body) and keeps what a request did not
// consume (a pipelined next request) for the next one. It never reads past the request's end: there
// the body ends (EOF), so no body can be longer than the Content-Length the gate checked.
#include <chrono>
#include <string>

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

class ConnectionStream : public httplib::Stream {
 public:
  /// `buffered` holds one whole request in its first `request_bytes`, then what came after it.
  ConnectionStream(int fd, std::string buffered, std::size_t request_bytes, std::chrono::milliseconds read_timeout,
                   std::chrono::milliseconds write_timeout);

  bool is_readable() const override;
  bool is_writable() const override;
  ssize_t read(char* ptr, std::size_t size) override;
  ssize_t write(const char* ptr, std::size_t size) override;
  void get_remote_ip_and_port(std::string& ip, int& port) const override;
  void get_local_ip_and_port(std::string& ip, int& port) const override;
  int socket() const override;

  /// The bytes read after the request. What the request left unread is dropped: a handler that
  /// answers before reading the body (a refusal before routing) must not turn the body into the
  /// next request.
  std::string takeBuffered();

 private:
  int fd_;
  std::string buffered_;
  std::size_t offset_ = 0;       ///< into buffered_
  std::size_t request_end_ = 0;  ///< where the request ends in buffered_
  std::chrono::milliseconds read_timeout_;
  std::chrono::milliseconds write_timeout_;
};

}  // namespace dash::http
