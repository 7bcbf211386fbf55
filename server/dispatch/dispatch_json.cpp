#include "server/dispatch/dispatch_json.h"

#include <set>

#include "server/dispatch/json_util.h"

namespace dash::dispatch {

using json_util::Json;
using namespace json_util;

namespace {

Json resultJson(ResultCode code, const std::string& message) {
  return {{"code", static_cast<int>(code)}, {"name", resultCodeName(code)}, {"message", message}};
}

Json controllerJson(const ControllerInfo& c, std::int64_t now_us) {
  Json j = {{"robot", c.robot},
            {"driver", c.driver},
            {"model", c.model},
            {"connected", c.connected},
            {"ready", c.ready},
            {"detail", c.detail},
            {"status", armStatusName(c.status)},
            {"dispatch_id", c.dispatch_id},
            {"result", resultJson(c.result, c.message)},
            {"gripper", c.gripper},
            {"joint_names", c.joint_names},
            {"reconnects", c.reconnects}};
  j["q"] = c.last_sample ? vec(c.last_sample->q) : Json(nullptr);
  j["state_age"] = c.last_report_us != 0 ? Json((now_us - c.last_report_us) * 1e-6) : Json(nullptr);
  j["connected_for"] = c.connected ? Json((now_us - c.connected_since_us) * 1e-6) : Json(nullptr);
  return j;
}

Json preflightJson(const PreflightReport& report) {
  Json checks = Json::array();
  for (const PreflightCheck& c : report.checks) {
    checks.push_back({{"name", c.name}, {"robot", c.robot}, {"passed", c.passed}, {"message", c.message}});
  }
  return {{"passed", report.passed}, {"reason", report.reason()}, {"checks", checks}};
}

constexpr std::size_t kMaxToleranceJoints = 64;
constexpr double kMaxGoalTime = 60.0;
constexpr double kMaxStartDelay = 3600.0;   ///< s
constexpr double kMaxStartTolerance = 0.5;  ///< rad (m): more is no start check at all
constexpr double kMaxTimeScale = 100.0;     ///< 100 times slower than planned
constexpr std::size_t kMaxJointNameLength = 100;

Json toleranceJson(const ToleranceSpec& t) {
  Json joints = Json::object();
  for (const auto& [name, value] : t.joints) joints[name] = value;
  return {{"all", t.all}, {"joints", joints}};
}

/// A number (every joint) or an object of joint name -> number, with "all" for the joints not named.
ToleranceSpec parseTolerance(const Json& value, const std::string& what) {
  ToleranceSpec out;
  if (value.is_number()) {
    out.all = value.get<double>();
  } else {
    DASH_THROW_UNLESS(value.is_object(), what + ": expected a number or an object of joint names to numbers");
    DASH_THROW_UNLESS(value.size() <= kMaxToleranceJoints, what + ": at most " + std::to_string(kMaxToleranceJoints) + " joints");
    out.all = -1.0;
    for (const auto& [name, v] : value.items()) {
      DASH_THROW_UNLESS(!name.empty() && name.size() <= kMaxJointNameLength, what + ": a joint name of 1 to 100 characters");
      DASH_THROW_UNLESS(v.is_number(), what + "." + name + ": expected a number");
      if (name == "all") {
        out.all = v.get<double>();
      } else {
        out.joints[name] = v.get<double>();
      }
    }
    DASH_THROW_UNLESS(out.all >= 0.0, what + ": needs \"all\" (the tolerance of the joints not named)");
  }
  out.validate(what);
  return out;
}

std::string textOf(const Json& value, const std::string& what) {
  if (value.is_string()) return value.get<std::string>();
  DASH_THROW_UNLESS(value.is_object(), what + ": expected a JSON object (or its text)");
  return value.dump();
}

}  // namespace

std::string controllerToJson(const ControllerInfo& c, std::int64_t now_us) { return controllerJson(c, now_us).dump(); }

std::string controllersToJson(const std::vector<ControllerInfo>& list, std::int64_t now_us) {
  Json a = Json::array();
  for (const ControllerInfo& c : list) a.push_back(controllerJson(c, now_us));
  return Json{{"controllers", a}}.dump();
}

std::string preflightToJson(const PreflightReport& report) { return preflightJson(report).dump(); }

namespace {

Json segmentsJson(const std::vector<SegmentRecord>& segments) {
  Json out = Json::array();
  for (const SegmentRecord& r : segments) {
    out.push_back({{"node", r.node},
                   {"kind", r.kind},
                   {"planned", Json::array({r.planned_start, r.planned_end})},
                   {"executed", Json::array({r.start < 0 ? Json(nullptr) : Json(r.start), r.end < 0 ? Json(nullptr) : Json(r.end)})}});
  }
  return out;
}

/// Execution by dependencies: where the arm is in its steps and what it waits for.
Json tpgArmJson(const ArmDispatchStatus& a) {
  return {{"step", a.step}, {"steps", a.steps}, {"waiting_for", a.waiting_for}, {"segments", segmentsJson(a.segments)}};
}

}  // namespace

std::string segmentsToJson(const std::vector<SegmentRecord>& segments) { return segmentsJson(segments).dump(); }

std::string dispatchStatusToJson(const DispatchStatus& s) {
  Json arms = Json::array();
  for (const ArmDispatchStatus& a : s.arms) {
    Json aj = {{"robot", a.robot},
               {"driver", a.driver},
               {"status", armStatusName(a.status)},
               {"done", a.done},
               {"result", resultJson(a.result, a.message)},
               {"duration", a.duration},
               {"t", a.last_sample_t},
               {"planned", vec(a.planned)},
               {"actual", vec(a.actual)},
               {"deviation", a.deviation},
               {"max_deviation", a.max_deviation},
               {"samples", a.samples},
               {"path_tolerance", vec(a.path_tolerance)},
               {"goal_tolerance", vec(a.goal_tolerance)}};
    if (s.execution == "tpg") aj.update(tpgArmJson(a));
    if (!a.trace.empty()) {
      Json trace = Json::array();
      for (const TracePoint& p : a.trace) trace.push_back(Json::array({p.t, vec(p.planned), vec(p.actual)}));
      aj["trace"] = trace;
    }
    arms.push_back(aj);
  }
  return Json{{"id", s.id},
              {"run_id", s.origin.run_id},
              {"requested_by", s.origin.requested_by},
              {"state", dispatchStateName(s.state)},
              {"reason", s.reason},
              {"final", s.final},
              {"scene", s.scene},
              {"planner", s.planner},
              {"execution", s.execution},
              {"time_scale", s.time_scale},
              {"duration", s.duration},
              {"elapsed", s.elapsed},
              {"tolerances",
               {{"start", s.start_tolerance},
                {"path", s.path_tolerance.all},
                {"goal", s.goal_tolerance.all},
                {"goal_time", s.goal_time_tolerance},
                {"path_by_joint", toleranceJson(s.path_tolerance)["joints"]},
                {"goal_by_joint", toleranceJson(s.goal_tolerance)["joints"]}}},
              {"arms", arms}}
      .dump();
}

DispatchRequestBody parseDispatchRequest(const std::string& body) {
  const std::string w = "request";
  const Json j = parseObject(body, w);
  DispatchRequestBody out;
  if (j.contains("run_id")) {
    const Json& id = j["run_id"];
    DASH_THROW_UNLESS(id.is_string() || id.is_number_integer(), "request.run_id: expected a string or an integer");
    out.run_id = id.is_string() ? id.get<std::string>() : std::to_string(id.get<long long>());
    DASH_THROW_UNLESS(!out.run_id.empty(), "request.run_id: empty");
  } else {
    out.plan_json = textOf(field(j, "plan", w), "request.plan");
    out.scene_json = textOf(field(j, "scene", w), "request.scene");
  }
  out.user = strOr(j, "user", "", w);
  DASH_THROW_UNLESS(out.user.size() <= 100, "request.user: at most 100 characters");
  if (j.contains("options")) {
    const Json& o = j["options"];
    DASH_THROW_UNLESS(o.is_object(), "request.options: expected an object");
    const std::string p = "request.options";
    if (o.contains("start_delay")) out.options.start_delay = num(o, "start_delay", p);
    if (o.contains("start_tolerance")) out.options.start_tolerance = num(o, "start_tolerance", p);
    if (o.contains("path_tolerance")) out.options.path_tolerance = parseTolerance(o["path_tolerance"], p + ".path_tolerance");
    if (o.contains("goal_tolerance")) out.options.goal_tolerance = parseTolerance(o["goal_tolerance"], p + ".goal_tolerance");
    if (o.contains("goal_time_tolerance")) {
      out.options.goal_time_tolerance = num(o, "goal_time_tolerance", p);
      DASH_THROW_UNLESS(*out.options.goal_time_tolerance > 0.0 && *out.options.goal_time_tolerance <= kMaxGoalTime,
                        p + ".goal_time_tolerance: must be in (0, 60] s");
    }
    out.options.time_scale = numOr(o, "time_scale", 1.0, p);
    if (o.contains("validate_geometry")) out.options.validate_geometry = boolOr(o, "validate_geometry", true, p);
    out.options.execution = strOr(o, "execution", "timed", p);
    DASH_THROW_UNLESS(out.options.execution == "timed" || out.options.execution == "tpg",
                      p + ".execution: \"timed\" (one common start) or \"tpg\" (by dependencies)");
    for (const char* key : {"start_delay", "start_tolerance"}) {
      DASH_THROW_UNLESS(!o.contains(key) || o[key].get<double>() >= 0.0, p + "." + key + ": must not be negative");
    }
    // Upper bounds too: a hostile number must not overflow the schedule's arithmetic or park a dispatch.
    DASH_THROW_UNLESS(out.options.start_delay.value_or(0.0) <= kMaxStartDelay, p + ".start_delay: at most 3600 s");
    DASH_THROW_UNLESS(out.options.start_tolerance.value_or(0.0) <= kMaxStartTolerance,
                      p + ".start_tolerance: at most 0.5 rad");
    DASH_THROW_UNLESS(out.options.time_scale > 0.0, p + ".time_scale: must be positive");
    DASH_THROW_UNLESS(out.options.time_scale <= kMaxTimeScale, p + ".time_scale: at most 100 (100 times slower)");
  }
  return out;
}

void checkToleranceJoints(const DispatchOptions& options, const Plan& plan) {
  std::set<std::string> known;
  for (const RobotTrajectory& r : plan.robots) known.insert(r.joint_names.begin(), r.joint_names.end());
  const std::string p = "request.options";
  if (options.path_tolerance) options.path_tolerance->validateJointNames(known, p + ".path_tolerance");
  if (options.goal_tolerance) options.goal_tolerance->validateJointNames(known, p + ".goal_tolerance");
}

std::string errorToJson(const std::string& kind, const std::string& reason, const PreflightReport* preflight) {
  Json j = {{"error", kind}, {"reason", reason}};
  if (preflight != nullptr) j["preflight"] = preflightJson(*preflight);
  return j.dump();
}

}  // namespace dash::dispatch
