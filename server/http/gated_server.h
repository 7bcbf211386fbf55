#pragma once
// GatedServer: cpp-httplib's Server behind a connection gate. httplib 0.11.4 gives each connection
// a worker thread from the moment it is accepted, reads headers without an overall deadline or a
// count limit, and counts chunked or compressed bodies only after decoding, if at all (issue 24:
// 64 slow clients locked everyone out; 300,000 headers and 50 MB bodies were accepted).
//
// Here one reader thread polls every connection until a whole request (head and body, within
// HeadLimits) has arrived, and only then hands it to a worker, which runs httplib's own request
// handling (routing, handlers, responses) on the buffered bytes. A connection that is slow, idle,
// or one too many waits on the reader, not on a worker:
// - a request must be complete `request_timeout` after its first byte (else 408 and close);
// - a kept-alive connection may idle `idle_timeout` before its next request (then closed);
// - at most `max_waiting` connections wait, holding at most `max_buffered_bytes` together; beyond,
//   the ones waiting longest are dropped;
// - at most `max_queued` whole requests wait for a worker; beyond, 503;
// - heads beyond the limits get 431, bodies 413, chunked 411, Content-Encoding 415.
// Workers are then busy only while a handler runs (an event stream holds one: see routes_events).
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "server/http/request_head.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

/// On a worker thread, inside a handler: whether the client of the request being handled has
/// closed its side (or reset) the connection. False elsewhere. A long handler (a console query)
/// asks it to stop work nobody waits for.
bool currentClientGone();

struct GateOptions {
  HeadLimits limits;
  std::chrono::milliseconds request_timeout{10000};  ///< first byte of a request to its last body byte
  std::chrono::milliseconds idle_timeout{5000};      ///< a connection's wait for its next request
  std::chrono::milliseconds write_timeout{5000};     ///< a worker's wait for a client to take its answer
  std::size_t max_waiting = 512;                     ///< connections the reader holds at once
  std::size_t max_buffered_bytes = 64 << 20;         ///< what they may have sent, together
  std::size_t max_queued = 256;                      ///< whole requests waiting for a worker; more: 503
  std::size_t workers = 64;                          ///< requests handled at once
  std::size_t max_requests_per_connection = 1000;
};

class GatedServer : public httplib::Server {
 public:
  explicit GatedServer(GateOptions options);
  ~GatedServer() override;
  GatedServer(const GatedServer&) = delete;
  GatedServer& operator=(const GatedServer&) = delete;

  /// After binding: httplib listens with a backlog of 5, so that a burst of connections beyond it
  /// waits for the kernel's SYN retry (1 s, then 3 s). Returns false if listen() refused.
  bool raiseListenBacklog(int backlog);

  /// Requests handed to the workers and not finished (running or queued).
  std::size_t inFlight() const { return in_flight_.load(); }

  /// After stop(): closes the waiting connections and waits for the workers' requests to end.
  /// Idempotent.
  void stopGate();

 private:
  struct Waiting;
  /// Called by httplib's accept loop for each new connection: hands it to the reader.
  bool process_and_close_socket(int sock) override;
  void admit(int fd, std::string buffered, std::size_t served);
  void readerLoop();
  /// Reads what arrived; returns false when the connection is finished with (closed or handed on).
  bool advance(Waiting& w, bool readable, std::chrono::steady_clock::time_point now);
  /// Closes the connections waiting longest until the waiting ones fit max_waiting and max_buffered_bytes.
  void dropOldest(std::vector<std::unique_ptr<Waiting>>& waiting) const;
  void serve(int fd, std::string request, std::size_t request_bytes, std::size_t served);
  void wake();

  const GateOptions options_;
  int wake_fd_ = -1;
  std::mutex mutex_;
  std::deque<std::unique_ptr<Waiting>> incoming_;
  bool stopping_ = false;
  std::atomic<std::size_t> in_flight_{0};  ///< requests handed to the workers and not done yet
  std::unique_ptr<httplib::ThreadPool> workers_;
  std::thread reader_;
};

}  // namespace dash::http
