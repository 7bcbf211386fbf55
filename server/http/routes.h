#pragma once
// The API's route groups, each registered on the server by one function. ApiContext holds what the
// handlers share; it outlives the httplib::Server.
#include <memory>
#include <string>

#include "server/http/batch_manager.h"
#include "server/http/event_hub.h"
#include "server/http/run_detail.h"
#include "server/http/run_queries.h"
#include "server/http/scene_cache.h"
#include "server/http/series_queries.h"
#include "server/http/static_files.h"

namespace httplib {
class Server;
}

namespace dash::http {

struct ApiContext {
  std::string db_path;
  std::string token;
  std::string executable;  ///< the dashbench binary (query-worker); empty: /proc/self/exe
  std::size_t max_body_bytes = 0;
  double query_timeout_seconds = 10;
  int max_event_streams = 32;
  bool dispatch_mounted = false;
  EventHub* hub = nullptr;
  BatchManager* batches = nullptr;
  SceneCache* scenes = nullptr;
  const StaticFiles* files = nullptr;
  RunQueries runs{""};
  RunDetail detail{""};
  SeriesQueries series{""};
};

/// GET /api/health, /api/info, /api/scenarios[/FAMILY], /api/planners
void registerCatalogRoutes(httplib::Server& server, ApiContext& ctx);
/// /api/batches: validate, submit, list, one, cancel, resume
void registerBatchRoutes(httplib::Server& server, ApiContext& ctx);
/// /api/runs: list, columns, CSV, one, events, timeline, plan, scene, tags, note
void registerRunRoutes(httplib::Server& server, ApiContext& ctx);
/// /api/series, /api/compare/overview, /api/query, /api/query/examples
void registerDataRoutes(httplib::Server& server, ApiContext& ctx);
/// GET /api/events: the server-sent event stream
void registerEventRoutes(httplib::Server& server, ApiContext& ctx);
/// Everything else: the dashboard's files (GET only), /vendor/ allow-list, 404 for unknown /api/ paths
void registerStaticRoutes(httplib::Server& server, ApiContext& ctx);

}  // namespace dash::http
