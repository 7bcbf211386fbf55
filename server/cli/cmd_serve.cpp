// dashbench serve: the HTTP server and web dashboard (server/http).
#include <signal.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "engine/core/check.h"
#include "engine/core/paths.h"
#include "server/cli/args.h"
#include "server/cli/command.h"
#include "server/http/http_server.h"
#include "server/http/static_files.h"
#include "server/http/token_file.h"

namespace dash::cli {

extern const char* const kServeHelp;
const char* const kServeHelp =
    "usage: dashbench serve [--host 127.0.0.1] [--port 8080] [--db data/results.db] [--token-file FILE]\n"
    "                       [--web DIR] [--max-workers N] [--max-runs N] [--query-timeout S]\n"
    "                       [--dispatch-state-timeout S]\n"
    "Serve the web dashboard and the JSON API (http://HOST:PORT/, API under /api/).\n"
    "  --host H         address to listen on (default 127.0.0.1: this machine only). Another address\n"
    "                   lets others read every result; changes still need the token.\n"
    "  --port P         default 8080; 0 picks a free port (the URL printed says which)\n"
    "  --db FILE        results database (default data/results.db; created if missing: at the first\n"
    "                   start the default one is a copy of data/demo.db, so the plots show real runs)\n"
    "  --token-file F   the token every change (launch, cancel, resume, tags, notes, dispatch) must\n"
    "                   send as 'Authorization: Bearer TOKEN' (default data/token; made at the first\n"
    "                   start, mode 0600, and printed once)\n"
    "  --web DIR        the dashboard's files (default: the source tree's web/, or $DASHBENCH_WEB)\n"
    "  --max-workers N  runs at once per batch, at most (default: the number of cores)\n"
    "  --max-runs N     the most runs one submitted batch may expand to (default 5000; 1..100000)\n"
    "  --query-timeout S\n"
    "                   the query console's time limit per query, in seconds (default 10; 0.1..600)\n"
    "  --dispatch-state-timeout S\n"
    "                   seconds a dispatched arm may go without reporting its state before every\n"
    "                   arm is stopped (default 0.5; between 0.05 and 10)\n"
    "Batches launched from the dashboard run each run in its own process; Ctrl-C stops the server and\n"
    "cancels them cleanly (resume them from the Launch page after the next start).\n";

namespace {

constexpr const char* kDefaultDb = "data/results.db";
constexpr const char* kDefaultTokenFile = "data/token";

bool isLoopback(const std::string& host) { return host == "127.0.0.1" || host == "localhost" || host == "::1"; }

/// A newcomer's first start: a copy of the demo database, so that the Compare page has plots at once.
void seedDefaultDb(const std::string& db_path) {
  namespace fs = std::filesystem;
  const fs::path demo = fs::path(dataDirectory()) / "demo.db";
  if (fs::exists(db_path) || !fs::exists(demo)) return;
  if (fs::path(db_path).has_parent_path()) fs::create_directories(fs::path(db_path).parent_path());
  fs::copy_file(demo, db_path);
  std::fprintf(stderr, "dashbench serve: %s did not exist: started it as a copy of %s (the demo runs)\n",
               db_path.c_str(), demo.c_str());
}

}  // namespace

int runServe(const std::vector<std::string>& words) {
  Args args(words, {.options = {"host", "port", "db", "token-file", "web", "max-workers", "max-runs", "query-timeout",
                                "dispatch-state-timeout"},
                    .flags = {}});
  DASH_THROW_UNLESS(args.positional().empty(), "serve takes no positional arguments (see --help)");
  http::ServerOptions options;
  options.host = args.get("host", "127.0.0.1");
  const long long port = args.integer("port", 8080);
  DASH_THROW_UNLESS(port >= 0 && port <= 65535, "--port must be between 0 (any free port) and 65535");
  options.port = static_cast<int>(port);
  options.db_path = args.get("db", kDefaultDb);
  options.web_root = args.get("web", "");
  options.max_batch_workers = static_cast<int>(args.integer("max-workers", 0));  // 0: the number of cores
  DASH_THROW_UNLESS(!args.has("max-workers") || (options.max_batch_workers >= 1 && options.max_batch_workers <= 1024),
                    "--max-workers must be between 1 and 1024");
  const long long max_runs = args.integer("max-runs", 5000);
  DASH_THROW_UNLESS(max_runs >= 1 && max_runs <= 100000, "--max-runs must be between 1 and 100000");
  options.max_batch_runs = static_cast<std::size_t>(max_runs);
  options.query_timeout_seconds = args.number("query-timeout", 10);
  DASH_THROW_UNLESS(options.query_timeout_seconds >= 0.1 && options.query_timeout_seconds <= 600,
                    "--query-timeout must be between 0.1 and 600 seconds");
  options.dispatch_state_timeout_seconds = args.number("dispatch-state-timeout", 0.5);
  DASH_THROW_UNLESS(options.dispatch_state_timeout_seconds >= 0.05 && options.dispatch_state_timeout_seconds <= 10,
                    "--dispatch-state-timeout must be between 0.05 and 10 seconds");
  if (!args.has("db")) seedDefaultDb(options.db_path);

  const std::string token_path = args.get("token-file", kDefaultTokenFile);
  const http::TokenFile token = http::loadOrCreateToken(token_path);
  options.token = token.token;
  if (token.too_permissive) {
    std::fprintf(stderr, "dashbench serve: warning: %s is readable by others; run: chmod 600 %s\n", token_path.c_str(),
                 token_path.c_str());
  }

  // Every thread the server starts inherits this mask: SIGINT and SIGTERM reach only sigwait below.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  signal(SIGPIPE, SIG_IGN);

  http::HttpServer server(options);
  server.start();
  std::fprintf(stderr, "dashbench serve: results database %s\n", options.db_path.c_str());
  if (!isLoopback(options.host)) {
    std::fprintf(stderr,
                 "dashbench serve: warning: listening on %s: anyone who can reach it can read the results; "
                 "changes need the token\n",
                 options.host.c_str());
  }
  for (const http::VendorFile& v : http::StaticFiles::vendorFiles()) {
    const std::filesystem::path web = options.web_root.empty() ? http::HttpServer::defaultWebRoot() : options.web_root;
    if (!std::filesystem::exists(web / "node_modules" / v.file)) {
      std::fprintf(stderr,
                   "dashbench serve: warning: %s is missing: the plots and the 3D view need the dashboard's "
                   "npm packages (run `npm ci` in %s)\n",
                   v.file, web.c_str());
      break;
    }
  }
  if (!server.dispatchMounted()) std::fprintf(stderr, "dashbench serve: the dispatch API is not part of this build\n");
  if (token.created) {
    std::printf("dashbench serve: new token (saved in %s, mode 0600; shown only this once):\n  %s\n",
                token_path.c_str(), token.token.c_str());
    std::printf("dashbench serve: open %s/#token=%s (signs this browser in)\n", server.url().c_str(),
                token.token.c_str());
  } else {
    std::printf("dashbench serve: open %s (the token for changes is in %s)\n", server.url().c_str(),
                token_path.c_str());
  }
  std::fflush(stdout);

  int sig = 0;
  sigwait(&stop_signals, &sig);
  std::fprintf(stderr, "dashbench serve: stopping (running batches are cancelled; resume them after the next start)\n");
  server.stop();
  return kExitOk;
}

}  // namespace dash::cli
