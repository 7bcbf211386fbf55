// /api/runs: the runs table (filter, sort, page), CSV export, one run's detail, events, timeline,
// plan and scene, and its tags and note.

#include "engine/core/check.h"
#include "engine/core/text_split.h"
#include "server/http/api_json.h"
#include "server/http/api_util.h"
#include "server/http/routes.h"

// clang-format off
#include <httplib.h>  // last: it must follow Eigen (see server/dispatch/dispatch_routes.h)
// clang-format on

namespace dash::http {

namespace {

constexpr const char* kRun = R"(/api/runs/([0-9A-Fa-f\-]{1,64}))";
constexpr std::int64_t kMaxPage = 5000;
constexpr std::int64_t kMaxCsvRows = 200000;

RunListRequest listRequest(const httplib::Request& req) {
  RunListRequest r;
  r.filter = param(req, "q");
  r.batch_id = param(req, "batch");
  r.uuids = splitList(param(req, "uuids"), ',', EmptyItems::kDrop);
  r.sort = param(req, "sort", "id");
  const std::string order = param(req, "order", "desc");
  if (order != "asc" && order != "desc") throw HttpError(400, "order: '" + order + "' is not asc or desc");
  r.descending = order == "desc";
  r.limit = intParam(req, "limit", 100, 1, kMaxPage);
  r.offset = intParam(req, "offset", 0, 0, INT64_MAX);
  r.columns = splitList(param(req, "columns"), ',', EmptyItems::kDrop);
  return r;
}

std::vector<std::string> stringList(const Json& body, const char* key) {
  std::vector<std::string> out;
  if (!body.contains(key)) return out;
  const Json& v = body[key];
  if (v.is_string()) return {v.get<std::string>()};
  if (!v.is_array()) throw HttpError(400, std::string(key) + ": expected a list of strings");
  for (const Json& item : v) {
    if (!item.is_string()) throw HttpError(400, std::string(key) + ": expected a list of strings");
    out.push_back(item.get<std::string>());
  }
  return out;
}

}  // namespace

void registerRunRoutes(httplib::Server& server, ApiContext& ctx) {
  server.Get("/api/runs/columns", guarded([&ctx](const httplib::Request&, httplib::Response& res) {
               replyJson(res, 200, ctx.runs.columnsJson());
             }));

  server.Get("/api/runs", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               replyJson(res, 200, ctx.runs.listJson(listRequest(req)));
             }));

  server.Get("/api/runs.csv", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               const std::string csv = ctx.runs.csv(listRequest(req), kMaxCsvRows);
               res.set_header("Content-Disposition", "attachment; filename=\"runs.csv\"");
               res.set_content(csv, "text/csv; charset=utf-8");
             }));

  server.Get(kRun, guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               replyJson(res, 200, ctx.detail.runJson(req.matches[1]));
             }));

  server.Get(std::string(kRun) + "/events", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               replyJson(res, 200,
                         ctx.detail.eventsJson(req.matches[1], param(req, "type", "all"),
                                               intParam(req, "offset", 0, 0, INT64_MAX),
                                               intParam(req, "limit", 200, 1, kMaxPage)));
             }));

  server.Get(std::string(kRun) + "/timeline", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               replyJson(res, 200, ctx.detail.timelineJson(req.matches[1], intParam(req, "max", 2000, 2, 20000)));
             }));

  server.Get(std::string(kRun) + "/plan", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               const auto plan = ctx.detail.planText(req.matches[1]);
               if (!plan)
                 throw HttpError(404, "run " + std::string(req.matches[1]) +
                                          " has no plan (it was not solved "
                                          "with motions)");
               replyJson(res, 200, *plan);
             }));

  server.Get(std::string(kRun) + "/scene", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               const RunScenario s = ctx.detail.scenario(req.matches[1]);
               replyJson(res, 200, ctx.scenes->sceneJson(s.family, s.params, s.seed));
             }));

  server.Post(std::string(kRun) + "/tags", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
                requireToken(req, ctx.token);
                const Json body = parseBodyObject(req);
                for (const auto& [key, value] : body.items()) {
                  if (key != "add" && key != "remove")
                    throw HttpError(400, "unknown key '" + key + "' (expected add, remove)");
                }
                ctx.detail.editTags(req.matches[1], stringList(body, "add"), stringList(body, "remove"));
                replyJson(res, 200, ctx.detail.annotationsJson(req.matches[1]));
              }));

  server.Delete(std::string(kRun) + "/tags/([^/]{1,64})",
                guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
                  requireToken(req, ctx.token);
                  ctx.detail.editTags(req.matches[1], {}, {req.matches[2]});
                  replyJson(res, 200, ctx.detail.annotationsJson(req.matches[1]));
                }));

  server.Put(std::string(kRun) + "/note", guarded([&ctx](const httplib::Request& req, httplib::Response& res) {
               requireToken(req, ctx.token);
               const Json body = parseBodyObject(req);
               if (!body.contains("note") || !body["note"].is_string()) throw HttpError(400, "note: expected a string");
               ctx.detail.setNote(req.matches[1], body["note"].get<std::string>());
               replyJson(res, 200, ctx.detail.annotationsJson(req.matches[1]));
             }));
}

}  // namespace dash::http
