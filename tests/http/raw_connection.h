#pragma once
// A loopback TCP connection for attacks a client library would not make: partial heads sent slowly,
// bodies that are never finished, streams held open. Sends never raise SIGPIPE.
#include <string>

namespace dash::http::testing {

class RawConnection {
 public:
  explicit RawConnection(int port);
  ~RawConnection();
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;

  bool connected() const { return fd_ >= 0; }
  /// False once the server closed the connection (or refused more bytes).
  bool send(const std::string& bytes);
  /// Reads until `marker` has arrived, the server closed, or `seconds` passed; returns all read so far.
  std::string readUntil(const std::string& marker, double seconds);
  /// Reads until the server closes or `seconds` pass.
  std::string readAll(double seconds);
  /// The status code of an answer's first line; 0 if there is none.
  static int statusOf(const std::string& answer);
  /// Sends `request` on a new connection to `port` and returns its answer's status (0: none within `seconds`).
  static int statusOfRequest(int port, const std::string& request, double seconds = 10);

 private:
  int fd_ = -1;
  std::string received_;
};

}  // namespace dash::http::testing
