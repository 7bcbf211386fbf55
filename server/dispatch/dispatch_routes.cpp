#include "server/dispatch/dispatch_routes.h"

#include <chrono>
#include <memory>
#include <string>

#include "engine/plan/plan_json.h"
#include "engine/scene/scene_json.h"
#include "server/dispatch/dispatch_json.h"
#include "server/dispatch/json_util.h"

namespace dash::dispatch {

namespace {

using json_util::Json;
constexpr const char* kJson = "application/json";
constexpr const char* kRobotPattern = "([A-Za-z0-9_.\\-]+)";

void reply(httplib::Response& res, int status, const std::string& body) {
  res.status = status;
  res.set_content(body, kJson);
}

/// Runs a handler with the token check and turns exceptions into JSON errors.
template <class Handler>
httplib::Server::Handler guarded(const RequestAuthorizer& authorized, Handler handler) {
  return [authorized, handler](const httplib::Request& req, httplib::Response& res) {
    if (!authorized || !authorized(req)) {
      reply(res, 401, errorToJson("unauthorized", "missing or wrong token"));
      return;
    }
    try {
      handler(req, res);
    } catch (const InputError& e) {
      reply(res, 400, errorToJson("bad_request", e.what()));
    } catch (const std::exception& e) {
      reply(res, 500, errorToJson("internal", e.what()));
    }
  };
}

void handleDispatch(DispatchService& service, const httplib::Request& req, httplib::Response& res) {
  DispatchRequestBody body = parseDispatchRequest(req.body);
  if (!body.run_id.empty()) {
    if (!service.config().resolve_run) {
      reply(res, 400, errorToJson("bad_request", "this server does not resolve run ids; send the plan and scene"));
      return;
    }
    const auto source = service.config().resolve_run(body.run_id);
    if (!source) {
      reply(res, 404, errorToJson("unknown_run", "no stored plan for run '" + body.run_id + "'"));
      return;
    }
    body.plan_json = source->plan_json;
    body.scene_json = source->scene_json;
  }
  Scene scene;
  Plan plan;
  try {
    scene = parseScene(body.scene_json, service.library(), "scene");
  } catch (const InputError& e) {
    reply(res, 422, errorToJson("bad_scene", e.what()));
    return;
  }
  try {
    plan = parsePlan(body.plan_json, "plan");
  } catch (const InputError& e) {
    reply(res, 422, errorToJson("bad_plan", e.what()));
    return;
  }
  const DispatchOutcome outcome = service.dispatch(plan, scene, body.options);
  if (!outcome.accepted) {
    Json j = Json::parse(errorToJson(outcome.error, outcome.reason, &outcome.preflight));
    if (outcome.status) j["dispatch"] = Json::parse(dispatchStatusToJson(*outcome.status));
    reply(res, outcome.http_status, j.dump());
    return;
  }
  const DispatchStatus& st = *outcome.status;
  Json j = {{"dispatch_id", st.id},
            {"state", dispatchStateName(st.state)},
            {"start_time_us", st.start_time_us},
            {"start_in", (st.start_time_us - service.now()) * 1e-6},
            {"preflight", Json::parse(preflightToJson(outcome.preflight))},
            {"dispatch", Json::parse(dispatchStatusToJson(st))}};
  reply(res, outcome.http_status, j.dump());
}

}  // namespace

void registerDispatchRoutes(httplib::Server& server, DispatchService& service, RequestAuthorizer authorized) {
  DispatchService* svc = &service;

  server.Get("/api/controllers", guarded(authorized, [svc](const httplib::Request&, httplib::Response& res) {
               reply(res, 200, controllersToJson(svc->controllers(), svc->now()));
             }));

  server.Get(std::string("/api/controllers/") + kRobotPattern + "/stream",
             guarded(authorized, [svc](const httplib::Request& req, httplib::Response& res) {
               const std::string robot = req.matches[1];
               const DispatchService::StreamHandle handle = svc->openStream(robot);
               const auto heartbeat = std::chrono::microseconds(
                   static_cast<std::int64_t>(svc->config().heartbeat_interval * 1e6));
               res.set_header("Cache-Control", "no-cache");
               res.set_header("X-Accel-Buffering", "no");
               res.set_chunked_content_provider(
                   "text/event-stream",
                   [stream = handle.stream, svc, heartbeat](std::size_t, httplib::DataSink& sink) {
                     std::vector<std::string> events;
                     if (!stream->next(events, heartbeat)) return false;
                     if (events.empty()) events.push_back(formatSse("ping", pingToJson(svc->now())));
                     for (const std::string& e : events) {
                       if (!sink.write(e.data(), e.size())) return false;
                     }
                     return true;
                   },
                   [svc, robot, session = handle.session](bool) {
                     svc->closeStream(robot, session, "its command stream closed");
                   });
             }));

  server.Post(std::string("/api/controllers/") + kRobotPattern + "/state",
              guarded(authorized, [svc](const httplib::Request& req, httplib::Response& res) {
                const std::string robot = req.matches[1];
                const AgentReport report = parseAgentReport(req.body);
                if (svc->report(robot, report) == ReportResult::kStaleSession) {
                  reply(res, 409, errorToJson("stale_session", "session '" + report.session + "' is not " + robot +
                                                                   "'s current connection; reconnect"));
                  return;
                }
                reply(res, 200, Json{{"server_time_us", svc->now()}}.dump());
              }));

  server.Post("/api/dispatch", guarded(authorized, [svc](const httplib::Request& req, httplib::Response& res) {
                handleDispatch(*svc, req, res);
              }));

  server.Post("/api/dispatch/abort", guarded(authorized, [svc](const httplib::Request& req, httplib::Response& res) {
                std::string reason = "abort requested";
                if (!req.body.empty()) {
                  const Json j = json_util::parseObject(req.body, "request");
                  reason = json_util::strOr(j, "reason", reason, "request");
                }
                const AbortOutcome out = svc->abort(reason);
                reply(res, 200, Json{{"aborted", out.had_dispatch},
                                     {"dispatch_id", out.dispatch_id},
                                     {"controllers_notified", out.controllers_notified},
                                     {"server_time_us", out.at_us}}
                                    .dump());
              }));

  server.Get("/api/dispatch", guarded(authorized, [svc](const httplib::Request& req, httplib::Response& res) {
               const bool trace = req.has_param("trace") && req.get_param_value("trace") != "0";
               const auto status = svc->status(trace);
               if (!status) {
                 reply(res, 404, errorToJson("none", "no dispatch yet"));
                 return;
               }
               reply(res, 200, dispatchStatusToJson(*status));
             }));
}

}  // namespace dash::dispatch
