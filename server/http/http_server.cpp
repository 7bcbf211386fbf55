#include "server/http/http_server.h"

#include <malloc.h>
#include <sqlite3.h>

#include <algorithm>
#include <condition_variable>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "engine/core/check.h"
#include "engine/log/results_db.h"
#include "engine/robots/robot_model.h"
#include "server/batch/batch_store.h"
#include "server/http/api_util.h"
#include "server/http/batch_manager.h"
#include "server/http/db_watcher.h"
#include "server/http/event_hub.h"
#include "server/http/request_guard.h"
#include "server/http/routes.h"
#include "server/http/scene_cache.h"
#include "server/http/static_files.h"
#include "server/dispatch/dispatch_routes.h"

// clang-format off
#include "server/http/gated_server.h"  // includes httplib.h
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

/// Bounds all SQLite allocations of the server process together: a query that slips past the
/// query console's limits fails with "out of memory" instead of taking the machine's memory.
constexpr std::int64_t kSqliteHeapLimit = std::int64_t{512} << 20;

/// The most runs a server may accept in one batch (--max-runs): the spec's byte bound (32 MB)
/// refuses long-labelled grids well before.
constexpr std::size_t kMaxBatchRuns = 100000;

/// Connections the kernel queues until the accept loop takes them (httplib's own is 5).
constexpr int kListenBacklog = 1024;

GateOptions gateOptions(const ServerOptions& o) {
  GateOptions g;
  g.limits.max_body_bytes = o.max_body_bytes;
  g.workers = static_cast<std::size_t>(o.threads);
  g.request_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.request_timeout_seconds * 1000));
  g.idle_timeout = std::chrono::milliseconds(static_cast<std::int64_t>(o.idle_timeout_seconds * 1000));
  return g;
}

const char* statusText(int status) {
  switch (status) {
    case 400:
      return "bad request";
    case 401:
      return "unauthorized";
    case 403:
      return "forbidden";
    case 404:
      return "not found";
    case 405:
      return "method not allowed";
    case 413:
      return "request body too large";
    case 414:
      return "request URI too long";
    case 416:
      return "range not satisfiable";
    default:
      return status >= 500 ? "internal server error" : "request refused";
  }
}

}  // namespace

struct HttpServer::Impl {
  explicit Impl(ServerOptions o)
      : options(std::move(o)),
        robots(RobotLibrary::loadDefault()),
        files(options.web_root),
        scenes(robots),
        server(gateOptions(options)) {}

  ServerOptions options;
  std::shared_ptr<const RobotLibrary> robots;
  EventHub hub;
  StaticFiles files;
  SceneCache scenes;
  std::unique_ptr<BatchManager> batches;
  std::unique_ptr<DbWatcher> watcher;
  ApiContext ctx;
  std::unique_ptr<dispatch::DispatchService> dispatch;
  std::shared_ptr<dispatch::DispatchRecorder> dispatch_recorder;  ///< every dispatch, into the results database
  GatedServer server;
  std::thread thread;
  int port = 0;
  std::mutex mutex;
  std::condition_variable cv;
  bool started = false;
  bool stopped = false;
  bool finished = false;  ///< stop() is done

  void configure();
};

std::string HttpServer::defaultWebRoot() {
  if (const char* env = std::getenv("DASHBENCH_WEB"); env != nullptr && *env != '\0') return env;
  return DASHBENCH_WEB_DIR;
}

HttpServer::HttpServer(ServerOptions options) {
  if (options.web_root.empty()) options.web_root = defaultWebRoot();
  DASH_THROW_UNLESS(!options.token.empty(), "the server needs a token");
  DASH_THROW_UNLESS(options.port >= 0 && options.port <= 65535, "--port: out of range 0..65535");
  DASH_THROW_UNLESS(options.max_body_bytes >= 1024, "the body size limit must be at least 1024 bytes");
  DASH_THROW_UNLESS(options.threads >= 2, "the server needs at least 2 worker threads");
  DASH_THROW_UNLESS(options.request_timeout_seconds >= 0.1 && options.request_timeout_seconds <= 3600 &&
                        options.idle_timeout_seconds >= 0.1 && options.idle_timeout_seconds <= 3600,
                    "request and idle timeouts must be within 0.1..3600 s");
  DASH_THROW_UNLESS(options.max_event_streams >= 1, "the event stream limit must be at least 1");
  DASH_THROW_UNLESS(options.query_timeout_seconds >= 0.1 && options.query_timeout_seconds <= 600,
                    "the query time limit must be within 0.1..600 s");
  DASH_THROW_UNLESS(options.max_batch_runs >= 1 && options.max_batch_runs <= kMaxBatchRuns,
                    "the run limit of a batch must be within 1.." + std::to_string(kMaxBatchRuns));
  DASH_THROW_UNLESS(std::filesystem::is_regular_file(std::filesystem::path(options.web_root) / "index.html"),
                    "web root " + options.web_root + " has no index.html");
  if (options.max_batch_workers <= 0)
    options.max_batch_workers = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  const std::filesystem::path parent = std::filesystem::path(options.db_path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
  {
    // Create and migrate the file, and the batch runner's tables, before any reader opens it.
    log::ResultsDb db(options.db_path);
    batch::BatchStore store(options.db_path);
  }
  impl_ = std::make_unique<Impl>(std::move(options));
  impl_->configure();
}

HttpServer::~HttpServer() { stop(); }

void HttpServer::Impl::configure() {
  batches = std::make_unique<BatchManager>(BatchManagerOptions{.db_path = options.db_path,
                                                               .executable = options.executable,
                                                               .max_running = options.max_running_batches,
                                                               .max_workers = options.max_batch_workers,
                                                               .max_runs = options.max_batch_runs},
                                           hub);
  ctx.db_path = options.db_path;
  ctx.token = options.token;
  ctx.executable = options.executable;
  ctx.query_timeout_seconds = options.query_timeout_seconds;
  ctx.max_body_bytes = options.max_body_bytes;
  ctx.hub = &hub;
  ctx.batches = batches.get();
  ctx.scenes = &scenes;
  ctx.files = &files;
  ctx.runs = RunQueries(options.db_path);
  ctx.detail = RunDetail(options.db_path);
  ctx.series = SeriesQueries(options.db_path);

  // Streams never take more than half the workers: the rest answer everything else.
  ctx.max_event_streams = std::min(options.max_event_streams, options.threads / 2);

  sqlite3_hard_heap_limit64(kSqliteHeapLimit);
  server.set_payload_max_length(options.max_body_bytes);
  server.set_default_headers(
      {{"X-Content-Type-Options", "nosniff"}, {"X-Frame-Options", "DENY"}, {"Referrer-Policy", "no-referrer"}});
  const bool loopback_only = isLoopbackName(options.host);
  server.set_pre_routing_handler([this, loopback_only](const httplib::Request& req, httplib::Response& res) {
    if (const std::optional<Refusal> refusal = refusalBeforeRouting(req, loopback_only, port)) {
      replyError(res, refusal->status, refusal->message);
      return httplib::Server::HandlerResponse::Handled;
    }
    return httplib::Server::HandlerResponse::Unhandled;
  });
  server.set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) replyError(res, res.status, statusText(res.status));
  });
  server.set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown exception";
    try {
      if (ep) std::rethrow_exception(ep);
    } catch (const std::exception& e) {
      what = e.what();
    } catch (...) {
    }
    replyError(res, 500, "internal error: " + what);
  });

  registerCatalogRoutes(server, ctx);
  registerBatchRoutes(server, ctx);
  registerRunRoutes(server, ctx);
  registerDataRoutes(server, ctx);
  registerEventRoutes(server, ctx);
  if (options.dispatch) {
    dispatch::DispatchConfig config;
    config.library = robots;
    config.state_timeout = config.sample_timeout = options.dispatch_state_timeout_seconds;
    config.resolve_run = [this](const std::string& run_id) -> std::optional<dispatch::PlanSource> {
      try {
        const std::optional<std::string> plan = ctx.detail.planText(run_id);
        if (!plan) return std::nullopt;
        const RunScenario s = ctx.detail.scenario(run_id);
        return dispatch::PlanSource{.plan_json = *plan, .scene_json = scenes.sceneJson(s.family, s.params, s.seed)};
      } catch (const HttpError&) {
        return std::nullopt;
      }
    };
    dispatch = std::make_unique<dispatch::DispatchService>(std::move(config));
    dispatch_recorder = std::make_shared<dispatch::DispatchRecorder>(options.db_path);
    dispatch->addListener(dispatch_recorder);
    const std::string token = options.token;
    dispatch::registerDispatchRoutes(
        server, *dispatch, [token](const httplib::Request& req) { return hasToken(req, token); },
        dispatch_recorder.get());
    ctx.dispatch_mounted = true;
  }
  registerStaticRoutes(server, ctx);
}

int HttpServer::start() {
  // Buffers of 256 KiB and more (an 8 MB console answer, a batch spec's expansion, a plan) get their
  // own mappings, given back to the system when freed. By default glibc raises this threshold after
  // the first such free, up to 32 MiB, and then keeps freed answers in its per-thread arenas: four
  // console clients left the server holding 312 MB after they were gone (issue 40, attack 3; 43 MB
  // with this). Process-wide, once: the server owns the process it runs in.
  mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.mutex);
    DASH_THROW_UNLESS(!m.started, "the server was started already");
    m.started = true;
  }
  int port = m.options.port;
  if (port == 0) {
    port = m.server.bind_to_any_port(m.options.host);
  } else if (!m.server.bind_to_port(m.options.host, port)) {
    port = -1;
  }
  DASH_THROW_UNLESS(port > 0, "cannot listen on " + m.options.host + ":" + std::to_string(m.options.port) +
                                  " (is another server using the port?)");
  m.port = port;
  DASH_THROW_UNLESS(m.server.raiseListenBacklog(kListenBacklog), "cannot set the listen backlog");
  m.watcher = std::make_unique<DbWatcher>(m.options.db_path, m.hub, m.options.poll_seconds);
  m.thread = std::thread([&m] { m.server.listen_after_bind(); });
  return port;
}

void HttpServer::stop() {
  if (!impl_) return;
  Impl& m = *impl_;
  {
    std::lock_guard lock(m.mutex);
    if (m.stopped) return;
    m.stopped = true;
  }
  m.hub.close();
  m.batches->shutdown();
  if (m.watcher) m.watcher->stop();
  if (m.dispatch) m.dispatch->shutdown();
  m.server.stop();
  if (m.thread.joinable()) m.thread.join();
  m.server.stopGate();
  {
    std::lock_guard lock(m.mutex);
    m.finished = true;
  }
  m.cv.notify_all();
}

void HttpServer::wait() {
  Impl& m = *impl_;
  std::unique_lock lock(m.mutex);
  m.cv.wait(lock, [&] { return m.finished; });
}

int HttpServer::port() const { return impl_->port; }

std::string HttpServer::url() const {
  const std::string& h = impl_->options.host;
  const std::string host =
      h == "0.0.0.0" || h.empty() ? "127.0.0.1" : (h.find(':') != std::string::npos ? "[" + h + "]" : h);
  return "http://" + host + ":" + std::to_string(impl_->port);
}

bool HttpServer::dispatchMounted() const { return impl_->ctx.dispatch_mounted; }

const ServerOptions& HttpServer::options() const { return impl_->options; }

}  // namespace dash::http
