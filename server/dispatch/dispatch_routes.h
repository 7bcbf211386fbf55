#pragma once
// Mounts a DispatchService on the project's HTTP server (cpp-httplib). Every route asks the server's
// `authorized` callback first (an empty callback refuses everything) and answers 401 on false.
//
//   GET  /api/controllers                      the registry: every agent, its state and last joint state
//   GET  /api/controllers/ROBOT/stream         an agent's command stream (server-sent events)
//   POST /api/controllers/ROBOT/state          an agent's state reports (batched samples, status)
//   POST /api/dispatch                         dispatch a plan: {"plan", "scene"} or {"run_id"}, "options"
//                                              202 started; 400 bad body; 404 unknown run; 409 busy,
//                                              arms not ready or a goal refused; 422 bad plan; 504 no answer
//   POST /api/dispatch/preflight               the pre-flight checks alone (same body): 200 with the
//                                              report, passed or not; nothing moves, nothing is recorded
//   POST /api/dispatch/abort                   abort every arm now ({"reason"} optional)
//   GET  /api/dispatch[?trace=1]               the current (or last) dispatch, per arm planned vs actual
//   GET  /api/dispatch/stream                  server-sent events for the dashboard: "dispatch" (the
//                                              status, on change, at most 10 Hz) and "controllers"
//                                              (the registry, every 0.5 s); fetch it with the token
//   GET  /api/dispatches[?limit=N&offset=M]    the recorded history, newest first (with a recorder)
//   GET  /api/dispatches/ID                    one recorded dispatch
//
// POST /api/dispatch records who asked: the body's "user" label (or the X-Dashbench-User header) and
// the client's address.
//
// Each open agent stream holds one of the server's worker threads: size the pool for the agents plus
// the ordinary requests (svr.new_task_queue = [] { return new httplib::ThreadPool(N); }).
#include <functional>

// Eigen (through dispatch_service.h) must come before httplib.h: httplib includes <resolv.h>,
// whose `_res` macro breaks Eigen's headers when they come later.
#include "server/dispatch/dispatch_recorder.h"
#include "server/dispatch/dispatch_service.h"

#include <httplib.h>

namespace dash::dispatch {

using RequestAuthorizer = std::function<bool(const httplib::Request&)>;

/// `history` (may be null: the history routes then answer 404) must outlive the server.
void registerDispatchRoutes(httplib::Server& server, DispatchService& service, RequestAuthorizer authorized,
                            const DispatchRecorder* history = nullptr);

}  // namespace dash::dispatch
