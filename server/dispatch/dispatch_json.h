#pragma once
// JSON views of the dispatch service's records, for the HTTP API and the server's own use (the
// dashboard, the results database). Deterministic field order.
#include <string>
#include <vector>

#include "server/dispatch/controller_info.h"
#include "server/dispatch/dispatch_service.h"
#include "server/dispatch/dispatch_status.h"
#include "server/dispatch/preflight.h"

namespace dash::dispatch {

/// {"robot", "driver", "model", "connected", "ready", "detail", "status", "dispatch_id", "result":
/// {"code", "name", "message"}, "gripper", "joint_names", "q", "state_age", "connected_for",
/// "reconnects"}; times relative to `now_us`.
std::string controllerToJson(const ControllerInfo& c, std::int64_t now_us);
/// {"controllers": [...]}
std::string controllersToJson(const std::vector<ControllerInfo>& list, std::int64_t now_us);
/// {"passed", "reason", "checks": [{"name", "robot", "passed", "message"}]}
std::string preflightToJson(const PreflightReport& report);
/// {"id", "run_id", "requested_by", "state", "reason", "final", "scene", "planner", "time_scale", "duration", "elapsed",
///  "tolerances": {...}, "arms": [{"robot", "driver", "status", "done", "result": {...}, "duration",
///  "t", "planned", "actual", "deviation", "max_deviation", "samples", "trace"?: [[t, planned, actual]]}]}
std::string dispatchStatusToJson(const DispatchStatus& status);
/// [{"node", "kind", "planned": [start, end], "executed": [start, end]}] (executed ends null where not
/// reached): execution by dependencies, per arm.
std::string segmentsToJson(const std::vector<SegmentRecord>& segments);

/// A dispatch request body: {"plan": {...} | "plan text", "scene": {...} | "scene text"} or
/// {"run_id": "..."}, with optional "options": {"start_delay", "start_tolerance", "path_tolerance",
/// "goal_tolerance", "goal_time_tolerance", "time_scale", "validate_geometry"} and "user" (a label for
/// the record, at most 100 characters). path_tolerance and goal_tolerance are a number (every joint)
/// or an object {"all": rad, "JOINT_NAME": rad, ...} (tolerances.h). Throws InputError on a malformed body.
struct DispatchRequestBody {
  std::string run_id;      ///< set instead of the texts for a stored run
  std::string user;        ///< who asks, as they say (the record's requested_by)
  std::string plan_json;
  std::string scene_json;
  DispatchOptions options;
};
DispatchRequestBody parseDispatchRequest(const std::string& body);
/// Throws InputError (a 400 naming request.options.path_tolerance.NAME or goal_tolerance.NAME) when a
/// per-joint tolerance names no joint of `plan`'s arms.
void checkToleranceJoints(const DispatchOptions& options, const Plan& plan);

/// {"error": kind, "reason": text} (plus "preflight" when given).
std::string errorToJson(const std::string& kind, const std::string& reason, const PreflightReport* preflight = nullptr);

}  // namespace dash::dispatch
