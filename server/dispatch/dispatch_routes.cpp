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

/// `text` with invalid UTF-8 replaced (U+FFFD): an error may quote bytes of the request, and
/// serialising those strictly threw from the error handler itself, a 500 (issue 40).
std::string validUtf8(const std::string& text) {
  return Json::parse(Json(text).dump(-1, ' ', false, Json::error_handler_t::replace)).get<std::string>();
}

bool isValidUtf8(const std::string& text) {
  try {
    (void)Json(text).dump();
    return true;
  } catch (const Json::type_error&) {
    return false;
  }
}

/// Runs a handler with the token check and turns exceptions into JSON errors.
template <class Handler>
httplib::Server::Handler guarded(const RequestAuthorizer& authorized, Handler handler) {
  return [authorized, handler](const httplib::Request& req, httplib::Response& res) {
    if (!authorized || !authorized(req)) {
      reply(res, 401, errorToJson("unauthorized", "missing or wrong token"));
      return;
    }
    if (!isValidUtf8(req.body)) {
      reply(res, 400, errorToJson("bad_request", "the request body is not valid UTF-8"));
      return;
    }
    try {
      handler(req, res);
    } catch (const InputError& e) {
      reply(res, 400, errorToJson("bad_request", validUtf8(e.what())));
    } catch (const std::exception& e) {
      reply(res, 500, errorToJson("internal", validUtf8(e.what())));
    }
  };
}

/// The plan and scene of a request body (inline, or a stored run's); false after answering an error.
bool loadPlan(DispatchService& service, DispatchRequestBody& body, Plan& plan, Scene& scene, httplib::Response& res) {
  if (!body.run_id.empty()) {
    if (!service.config().resolve_run) {
      reply(res, 400, errorToJson("bad_request", "this server does not resolve run ids; send the plan and scene"));
      return false;
    }
    const auto source = service.config().resolve_run(body.run_id);
    if (!source) {
      reply(res, 404, errorToJson("unknown_run", "no stored plan for run '" + body.run_id + "'"));
      return false;
    }
    body.plan_json = source->plan_json;
    body.scene_json = source->scene_json;
  }
  try {
    scene = parseScene(body.scene_json, service.library(), "scene");
  } catch (const InputError& e) {
    reply(res, 422, errorToJson("bad_scene", e.what()));
    return false;
  }
  try {
    plan = parsePlan(body.plan_json, "plan");
  } catch (const InputError& e) {
    reply(res, 422, errorToJson("bad_plan", e.what()));
    return false;
  }
  checkToleranceJoints(body.options, plan);  // a 400: the request, not the plan, is wrong
  return true;
}

void handlePreflight(DispatchService& service, const httplib::Request& req, httplib::Response& res) {
  DispatchRequestBody body = parseDispatchRequest(req.body);
  Scene scene;
  Plan plan;
  if (!loadPlan(service, body, plan, scene, res)) return;
  const PreflightReport report = service.check(plan, scene, body.options);
  reply(res, 200, preflightToJson(report));
}

void handleDispatch(DispatchService& service, const httplib::Request& req, httplib::Response& res) {
  DispatchRequestBody body = parseDispatchRequest(req.body);
  Scene scene;
  Plan plan;
  if (!loadPlan(service, body, plan, scene, res)) return;
  DispatchOrigin origin;
  const std::string user = !body.user.empty() ? body.user : req.get_header_value("X-Dashbench-User").substr(0, 100);
  origin.requested_by = validUtf8(user);  // 100 bytes may cut a character
  origin.client = req.remote_addr;
  origin.run_id = body.run_id;
  const DispatchOutcome outcome = service.dispatch(plan, scene, body.options, origin);
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

int intParam(const httplib::Request& req, const char* name, int fallback, int lo, int hi) {
  if (!req.has_param(name)) return fallback;
  const std::string text = req.get_param_value(name);
  try {
    std::size_t used = 0;
    const int v = std::stoi(text, &used);
    DASH_THROW_UNLESS(used == text.size() && v >= lo && v <= hi, "");
    return v;
  } catch (const std::exception&) {
    throw InputError(std::string(name) + ": expected an integer in " + std::to_string(lo) + ".." + std::to_string(hi));
  }
}

/// The dashboard's live view: the dispatch status whenever it changes (polled at 10 Hz here, so
/// every page sees the same rate whatever the agents report), and the registry every 0.5 s.
void streamStatus(DispatchService& svc, httplib::Response& res) {
  res.set_header("Cache-Control", "no-cache");
  res.set_header("X-Accel-Buffering", "no");
  struct State {
    std::string last_status;
    std::int64_t last_controllers_us = 0;
    std::int64_t last_write_us = 0;
    bool first = true;
  };
  auto state = std::make_shared<State>();
  res.set_chunked_content_provider(
      "text/event-stream", [svc = &svc, state](std::size_t, httplib::DataSink& sink) {
        if (!state->first && svc->sleepUnlessStopping(std::chrono::milliseconds(100))) return false;
        state->first = false;
        std::string out;
        const std::int64_t t = svc->now();
        if (const auto status = svc->status(false)) {
          const std::string text = dispatchStatusToJson(*status);
          if (text != state->last_status) {
            state->last_status = text;
            out += formatSse("dispatch", text);
          }
        }
        if (t - state->last_controllers_us >= 500000) {
          state->last_controllers_us = t;
          out += formatSse("controllers", controllersToJson(svc->controllers(), t));
        }
        if (out.empty() && t - state->last_write_us >= 2000000) out = ": keep-alive\n\n";
        if (out.empty()) return true;
        state->last_write_us = t;
        return sink.write(out.data(), out.size());
      });
}

void handleHistory(const DispatchRecorder* history, const httplib::Request& req, httplib::Response& res) {
  if (history == nullptr) {
    reply(res, 404, errorToJson("none", "this server does not record dispatches"));
    return;
  }
  const int limit = intParam(req, "limit", 50, 1, 1000);
  const int offset = intParam(req, "offset", 0, 0, 1 << 30);
  reply(res, 200, history->historyJson(limit, offset));
}

void handleRecord(const DispatchRecorder* history, const httplib::Request& req, httplib::Response& res) {
  const std::string record = history != nullptr ? history->recordJson(req.matches[1]) : "";
  if (record.empty()) {
    reply(res, 404, errorToJson("unknown_dispatch", "no recorded dispatch '" + std::string(req.matches[1]) + "'"));
    return;
  }
  reply(res, 200, record);
}

/// A controller agent's command stream (server-sent events), with a ping when nothing else comes.
void streamCommands(DispatchService* svc, const httplib::Request& req, httplib::Response& res) {
  const std::string robot = req.matches[1];
  const DispatchService::StreamHandle handle = svc->openStream(robot);
  const auto heartbeat =
      std::chrono::microseconds(static_cast<std::int64_t>(svc->config().heartbeat_interval * 1e6));
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
      [svc, robot, session = handle.session](bool) { svc->closeStream(robot, session, "its command stream closed"); });
}

void handleReport(DispatchService& svc, const httplib::Request& req, httplib::Response& res) {
  const std::string robot = req.matches[1];
  const AgentReport report = parseAgentReport(req.body);
  if (svc.report(robot, report) == ReportResult::kStaleSession) {
    reply(res, 409, errorToJson("stale_session", "session '" + report.session + "' is not " + robot +
                                                     "'s current connection; reconnect"));
    return;
  }
  reply(res, 200, Json{{"server_time_us", svc.now()}}.dump());
}

void handleAbort(DispatchService& svc, const httplib::Request& req, httplib::Response& res) {
  std::string reason = "abort requested";
  if (!req.body.empty()) {
    const Json j = json_util::parseObject(req.body, "request");
    reason = json_util::strOr(j, "reason", reason, "request");
  }
  const AbortOutcome out = svc.abort(reason);
  reply(res, 200, Json{{"aborted", out.had_dispatch},
                       {"dispatch_id", out.dispatch_id},
                       {"controllers_notified", out.controllers_notified},
                       {"server_time_us", out.at_us}}
                      .dump());
}

void handleStatus(DispatchService& svc, const httplib::Request& req, httplib::Response& res) {
  const bool trace = req.has_param("trace") && req.get_param_value("trace") != "0";
  const auto status = svc.status(trace);
  if (!status) {
    reply(res, 404, errorToJson("none", "no dispatch yet"));
    return;
  }
  reply(res, 200, dispatchStatusToJson(*status));
}

}  // namespace

void registerDispatchRoutes(httplib::Server& server, DispatchService& service, RequestAuthorizer authorized,
                            const DispatchRecorder* history) {
  DispatchService* svc = &service;
  const std::string controller = std::string("/api/controllers/") + kRobotPattern;
  using Req = httplib::Request;
  using Res = httplib::Response;
  server.Get("/api/dispatch/stream", guarded(authorized, [svc](const Req&, Res& res) { streamStatus(*svc, res); }));
  server.Get("/api/dispatches",
             guarded(authorized, [history](const Req& req, Res& res) { handleHistory(history, req, res); }));
  server.Get(R"(/api/dispatches/([A-Za-z0-9_.\-]+))",
             guarded(authorized, [history](const Req& req, Res& res) { handleRecord(history, req, res); }));
  server.Get("/api/controllers", guarded(authorized, [svc](const Req&, Res& res) {
               reply(res, 200, controllersToJson(svc->controllers(), svc->now()));
             }));
  server.Get(controller + "/stream",
             guarded(authorized, [svc](const Req& req, Res& res) { streamCommands(svc, req, res); }));
  server.Post(controller + "/state",
              guarded(authorized, [svc](const Req& req, Res& res) { handleReport(*svc, req, res); }));
  server.Post("/api/dispatch", guarded(authorized, [svc](const Req& req, Res& res) { handleDispatch(*svc, req, res); }));
  server.Post("/api/dispatch/preflight",
              guarded(authorized, [svc](const Req& req, Res& res) { handlePreflight(*svc, req, res); }));
  server.Post("/api/dispatch/abort",
              guarded(authorized, [svc](const Req& req, Res& res) { handleAbort(*svc, req, res); }));
  server.Get("/api/dispatch", guarded(authorized, [svc](const Req& req, Res& res) { handleStatus(*svc, req, res); }));
}

}  // namespace dash::dispatch
