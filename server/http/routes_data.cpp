// /api/series and /api/compare/overview (the Compare page's plots), /api/query (the read-only SQL
// console, with the guards of `dashbench db query`) and /api/query/examples.

#include <atomic>
#include <memory>

#include "engine/log/db_query.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/query_process.h"
#include "server/http/routes.h"
#include "server/http/gated_server.h"  // after routes.h: httplib must follow Eigen

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

constexpr std::int64_t kMaxQueryRows = 10000;
// What one query may cost the server (issue 24: a 64 MB cell limit let one query return 640 MB and
// peak at 2.6 GB). The process-wide SQLite heap limit (HttpServer) bounds what is left over.
constexpr int kMaxQueryCellBytes = 4 << 20;  ///< a stored plan is well below this
constexpr int kMaxQueryColumns = 200;
constexpr std::int64_t kMaxQueryResultBytes = 8 << 20;
constexpr int kMaxConcurrentQueries = 4;  ///< more at once get 503
constexpr const char* kPrivateAdvice =
    " without the server's token (as GET /api/dispatches): send 'Authorization: Bearer TOKEN'";
constexpr const char* kTimeLimitAdvice = "; narrow it, or raise the limit (dashbench serve --query-timeout)";

const char* guardName(log::QueryGuard g) {
  switch (g) {
    case log::QueryGuard::Write:
      return "write";
    case log::QueryGuard::Attach:
      return "attach";
    case log::QueryGuard::Pragma:
      return "pragma";
    case log::QueryGuard::Transaction:
      return "transaction";
    case log::QueryGuard::OneStatement:
      return "one_statement";
    case log::QueryGuard::TimeLimit:
      return "time_limit";
    case log::QueryGuard::Function:
      return "function";
    case log::QueryGuard::PrivateTable:
      return "token";
  }
  return "guard";
}

/// What GET /api/dispatches keeps behind the token (who dispatched, from which address), the
/// console keeps too: a query without the token cannot read these tables (issue 40).
std::vector<std::string> privateTables(const httplib::Request& req, const ApiContext& ctx) {
  if (hasToken(req, ctx.token)) return {};
  return {"dash_dispatches", "dash_dispatch_arms"};
}

Json examples() {
  auto q = [](const char* title, const char* sql) { return Json{{"title", title}, {"sql", sql}}; };
  return Json::array({
      q("Runs per status", "SELECT status, count(*) AS runs FROM dash_runs GROUP BY status ORDER BY runs DESC"),
      q("Mean time per configuration and object count (solved runs)",
        "SELECT c.name AS config, r.family, json_extract(r.params, '$.objects') AS objects, count(*) AS runs,\n"
        "       round(avg(r.total_time), 4) AS mean_total_s, round(avg(r.time_task_query), 4) AS mean_task_query_s\n"
        "FROM dash_runs r JOIN dash_planner_configs c ON c.id = r.planner_config_id\n"
        "WHERE r.status = 'solved' GROUP BY 1, 2, 3 ORDER BY 1, 2, 3"),
      q("Largest representations",
        "SELECT uuid, family, params, task_vertices, task_hyperarcs, motion_vertices, motion_hyperarcs\n"
        "FROM dash_runs ORDER BY motion_vertices DESC, task_vertices DESC LIMIT 20"),
      q("Constraints and the conflicts that caused them",
        "SELECT r.uuid, k.t, k.iteration, k.kind, k.action, k.content, k.conflict\n"
        "FROM dash_constraints k JOIN dash_runs r ON r.id = k.run_id ORDER BY r.id, k.t LIMIT 200"),
      q("Runs that did not solve, and why",
        "SELECT uuid, family, params, planner, status, error, exit_signal FROM dash_runs\n"
        "WHERE status NOT IN ('solved', 'running') ORDER BY id DESC LIMIT 50"),
      q("Tagged runs",
        "SELECT r.uuid, t.tag, r.note FROM dash_run_tags t JOIN dash_runs r ON r.id = t.run_id ORDER BY t.tag"),
      q("Planner Arena's runs view", "SELECT * FROM runs LIMIT 20"),
      q("Tables and views", "SELECT type, name FROM sqlite_schema WHERE type IN ('table', 'view') ORDER BY type, name"),
  });
}

}  // namespace

void registerDataRoutes(httplib::Server& server, ApiContext& ctx) {
  server.Get("/api/series", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               SeriesRequest r;
               r.family = param(req, "family");
               r.x = param(req, "x", "objects");
               r.group_by = param(req, "group_by", "config");
               r.split = param(req, "split");
               r.filter = param(req, "q");
               r.include_unsolved = param(req, "include_unsolved", "0") == "1";
               replyJson(res, 200, ctx.series.seriesJson(r));
             }));

  server.Get("/api/compare/overview", guarded([&ctx](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200, ctx.series.overviewJson());
             }));

  server.Get("/api/query/examples", guarded([](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200, jsonText(Json{{"examples", examples()}}));
             }));

  // Read-only by construction (db_query.h), so it needs no token; it is a POST only because SQL is long.
  auto running = std::make_shared<std::atomic<int>>(0);
  server.Post(
      "/api/query", guarded([&ctx, running](const httplib::Request& req, httplib::Response& res) {
        const Json body = parseBodyObject(req);
        if (!body.contains("sql") || !body["sql"].is_string()) throw HttpError(400, "sql: expected a string");
        std::int64_t max_rows = 1000;
        if (body.contains("max_rows")) max_rows = intMember(body, "max_rows", 1, kMaxQueryRows);
        const ConcurrencySlot slot(*running, kMaxConcurrentQueries, "too many queries at once; try again in a moment");
        try {
          // In a child process with CPU, memory and wall-clock limits (query_process.h).
          std::string answer = runQueryInChild(ctx.executable, ctx.db_path, body["sql"].get<std::string>(),
                                               log::QueryLimits{.max_rows = max_rows,
                                                                .timeout_seconds = ctx.query_timeout_seconds,
                                                                .max_cell_bytes = kMaxQueryCellBytes,
                                                                .max_columns = kMaxQueryColumns,
                                                                .max_result_bytes = kMaxQueryResultBytes,
                                                                .time_limit_advice = kTimeLimitAdvice,
                                                                .private_tables = privateTables(req, ctx),
                                                                .private_advice = kPrivateAdvice},
                                               currentClientGone);
          res.status = 200;
          res.body = std::move(answer);  // passed on as the query process wrote it
          res.set_header("Content-Type", kJsonType);
        } catch (const log::QueryRefused& e) {
          // QueryRefused's messages start with "refused:" already.
          const std::string what = e.what();
          const std::string message = what.rfind("refused:", 0) == 0 ? what : "refused: " + what;
          const int status = e.guard() == log::QueryGuard::PrivateTable ? 401 : 403;
          replyJson(res, status, jsonText(Json{{"error", message}, {"guard", guardName(e.guard())}}));
        }
      }));
}

}  // namespace dash::http
