#pragma once
// HttpServer: `dashbench serve`. One cpp-httplib server with the JSON API under /api/ (routes.h),
// server-sent events, the dispatch API when the build has it (server/dispatch), and the dashboard's
// static files. It owns the launch queue (BatchManager: batches run in their own processes, driven
// from a runner thread, never from an HTTP worker) and the database watcher that feeds live updates.
//
// Safety, by default: it listens on loopback only and refuses requests whose Host header names
// another host (DNS rebinding); every request that changes something needs the token, and a browser
// request that changes something must come from the server's own origin; requests are read whole
// by a connection gate (gated_server.h) with limits on time, head size, header count, body size and
// connections before a worker sees them; JSON bodies are limited in depth; event streams and SQL
// queries are capped; errors are JSON with a 4xx/5xx status and never end the process; the static
// file server cannot leave the web root; no CORS headers are ever sent, so other origins cannot
// read answers or send the token. docs/http-api.md lists the limits.
#include <memory>
#include <string>

namespace dash::http {

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;                          ///< 0: any free port (tests)
  std::string db_path = "data/results.db";  ///< created (with its folder) if missing
  std::string web_root;                     ///< empty: defaultWebRoot()
  std::string token;                        ///< required: what writes must send as a Bearer token
  std::string executable;                   ///< the dashbench binary that runs each run; empty: /proc/self/exe
  std::size_t max_body_bytes = 1 << 20;     ///< larger request bodies get 413
  int threads = 64;                         ///< HTTP workers (each open event stream holds one)
  int max_event_streams = 32;               ///< open /api/events streams at once (at most threads / 2); more: the oldest is ended
  double request_timeout_seconds = 10;      ///< a request's first byte to its last, else 408
  double query_timeout_seconds = 10;        ///< a console query's time limit (its process is killed then)
  double idle_timeout_seconds = 5;          ///< a kept-alive connection's wait for its next request
  double poll_seconds = 0.5;                ///< database watcher period
  int max_batch_workers = 0;                ///< runs at once per batch, at most; 0: the number of cores
  int max_running_batches = 1;              ///< more wait queued
  std::size_t max_batch_runs = 5000;        ///< a submitted spec that expands to more runs is refused
  bool dispatch = true;                     ///< mount the dispatch API
  /// s without a state report (or a joint state) from a dispatched arm before every arm is stopped
  double dispatch_state_timeout_seconds = 0.5;
};

class HttpServer {
 public:
  /// Checks the options and prepares the database (creates and migrates it). Throws InputError.
  explicit HttpServer(ServerOptions options);
  ~HttpServer();  ///< stop()
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  /// Binds and serves on a background thread; returns the port. Throws InputError if it cannot bind.
  int start();
  /// Ends the event streams, cancels running batches (their runs are recorded 'cancelled': resume
  /// them later), stops the dispatch service and the listener. Idempotent; any thread.
  void stop();
  /// Blocks until stop() has finished.
  void wait();

  int port() const;
  /// "http://127.0.0.1:8080"
  std::string url() const;
  bool dispatchMounted() const;
  const ServerOptions& options() const;

  /// $DASHBENCH_WEB if set, else the source tree's web/.
  static std::string defaultWebRoot();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace dash::http
