#include "server/dispatch/dispatch_protocol.h"

#include <fstream>

#include <algorithm>

#include "server/dispatch/json_util.h"

namespace dash::dispatch {

using json_util::Json;
using namespace json_util;

namespace {

Json trajectoryToJson(const ArmTrajectory& t) {
  Json points = Json::array();
  for (const TrajectoryWaypoint& p : t.points) {
    points.push_back({{"positions", vec(p.positions)},
                      {"velocities", vec(p.velocities)},
                      {"time_from_start", p.time_from_start}});
  }
  Json gripper = Json::array();
  for (const GripperCommand& g : t.gripper) {
    gripper.push_back({{"t", g.t}, {"action", gripperActionName(g.action)}, {"object", g.object}});
  }
  return {{"robot", t.robot}, {"joint_names", t.joint_names}, {"points", points}, {"gripper", gripper}};
}

ArmTrajectory trajectoryFromJson(const Json& j, const std::string& path) {
  DASH_THROW_UNLESS(j.is_object(), path + ": expected an object");
  ArmTrajectory t;
  t.robot = strOr(j, "robot", "", path);
  t.joint_names = strings(field(j, "joint_names", path), path + ".joint_names");
  const Json& points = field(j, "points", path);
  DASH_THROW_UNLESS(points.is_array(), path + ".points: expected an array");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string p = path + ".points[" + std::to_string(i) + "]";
    const Json& pj = points[i];
    DASH_THROW_UNLESS(pj.is_object(), p + ": expected an object");
    TrajectoryWaypoint w;
    w.positions = toVec(field(pj, "positions", p), p + ".positions");
    w.velocities = pj.contains("velocities") ? toVec(pj["velocities"], p + ".velocities")
                                             : JointVector::Zero(w.positions.size());
    w.time_from_start = num(pj, "time_from_start", p);
    t.points.push_back(w);
  }
  if (j.contains("gripper")) {
    const Json& gripper = j["gripper"];
    DASH_THROW_UNLESS(gripper.is_array(), path + ".gripper: expected an array");
    for (std::size_t i = 0; i < gripper.size(); ++i) {
      const std::string p = path + ".gripper[" + std::to_string(i) + "]";
      GripperCommand g;
      g.t = num(gripper[i], "t", p);
      const std::string action = str(gripper[i], "action", p);
      DASH_THROW_UNLESS(action == "grasp" || action == "release", p + ".action: expected grasp or release");
      g.action = action == "grasp" ? GripperCommand::Action::kGrasp : GripperCommand::Action::kRelease;
      g.object = strOr(gripper[i], "object", "", p);
      t.gripper.push_back(g);
    }
    std::stable_sort(t.gripper.begin(), t.gripper.end(),
                     [](const GripperCommand& a, const GripperCommand& b) { return a.t < b.t; });
  }
  return t;
}

}  // namespace

std::string helloToJson(const HelloMessage& m) {
  return Json{{"session", m.session}, {"server_time_us", m.server_time_us}, {"robot", m.robot}, {"clock", m.clock}}.dump();
}

HelloMessage parseHello(const std::string& text) {
  const Json j = parseObject(text, "hello");
  HelloMessage m{str(j, "session", "hello"), int64(j, "server_time_us", "hello"), strOr(j, "robot", "", "hello"),
                 strOr(j, "clock", "", "hello")};
  DASH_THROW_UNLESS(m.clock.size() <= kMaxClockIdLength, "hello.clock: too long");
  return m;
}

std::string steadyClockId() {
  // The steady clock is CLOCK_MONOTONIC: one clock per boot of one machine, named by its boot id.
  static const std::string id = [] {
    std::ifstream in("/proc/sys/kernel/random/boot_id");
    std::string text;
    std::getline(in, text);
    return text.size() <= kMaxClockIdLength ? text : std::string();
  }();
  return id;
}

std::string pingToJson(std::int64_t server_time_us) { return Json{{"server_time_us", server_time_us}}.dump(); }

std::string trajectoryCommandToJson(const TrajectoryCommand& c) {
  Json limits = {{"start_tolerance", c.limits.start_tolerance}, {"goal_time_tolerance", c.limits.goal_time_tolerance}};
  if (c.limits.goal_tolerance.size() > 0) limits["goal_tolerance"] = vec(c.limits.goal_tolerance);
  return Json{{"dispatch_id", c.dispatch_id}, {"trajectory", trajectoryToJson(c.trajectory)}, {"limits", limits}}.dump();
}

TrajectoryCommand parseTrajectoryCommand(const std::string& text) {
  const Json j = parseObject(text, "trajectory");
  TrajectoryCommand c;
  c.dispatch_id = str(j, "dispatch_id", "trajectory");
  c.trajectory = trajectoryFromJson(field(j, "trajectory", "trajectory"), "trajectory.trajectory");
  if (j.contains("limits")) {
    const Json& l = j["limits"];
    DASH_THROW_UNLESS(l.is_object(), "trajectory.limits: expected an object");
    c.limits.start_tolerance = numOr(l, "start_tolerance", c.limits.start_tolerance, "trajectory.limits");
    if (l.contains("goal_tolerance")) {
      const Json& g = l["goal_tolerance"];
      if (g.is_number()) {
        const double v = g.get<double>();
        c.limits.goal_tolerance = JointVector::Constant(static_cast<Eigen::Index>(c.trajectory.joint_names.size()), v);
      } else {
        c.limits.goal_tolerance = toVec(g, "trajectory.limits.goal_tolerance");
      }
      DASH_THROW_UNLESS(c.limits.goal_tolerance.size() == static_cast<Eigen::Index>(c.trajectory.joint_names.size()) &&
                            (c.limits.goal_tolerance.array() >= 0.0).all(),
                        "trajectory.limits.goal_tolerance: one non-negative number per joint");
    }
    c.limits.goal_time_tolerance = numOr(l, "goal_time_tolerance", c.limits.goal_time_tolerance, "trajectory.limits");
  }
  return c;
}

std::string startCommandToJson(const StartCommand& c) {
  return Json{{"dispatch_id", c.dispatch_id}, {"start_time_us", c.start_time_us}}.dump();
}

StartCommand parseStartCommand(const std::string& text) {
  const Json j = parseObject(text, "start");
  return {str(j, "dispatch_id", "start"), int64(j, "start_time_us", "start")};
}

std::string abortCommandToJson(const AbortCommand& c) {
  return Json{{"dispatch_id", c.dispatch_id}, {"reason", c.reason}}.dump();
}

AbortCommand parseAbortCommand(const std::string& text) {
  const Json j = parseObject(text, "abort");
  return {strOr(j, "dispatch_id", "", "abort"), strOr(j, "reason", "", "abort")};
}

std::string agentReportToJson(const AgentReport& r) {
  Json samples = Json::array();
  for (const JointSample& s : r.samples) {
    Json sj = {{"t_us", s.t_us}, {"q", vec(s.q)}};
    if (s.qd.size() > 0) sj["qd"] = vec(s.qd);
    samples.push_back(sj);
  }
  return Json{{"session", r.session},
              {"driver", r.driver},
              {"model", r.model},
              {"joint_names", r.joint_names},
              {"ready", r.ready},
              {"detail", r.detail},
              {"status", armStatusName(r.status)},
              {"dispatch_id", r.dispatch_id},
              {"result", {{"code", static_cast<int>(r.result)}, {"name", resultCodeName(r.result)}, {"message", r.message}}},
              {"gripper", r.gripper},
              {"samples", samples}}
      .dump();
}

AgentReport parseAgentReport(const std::string& text) {
  const std::string w = "state";
  const Json j = parseObject(text, w);
  AgentReport r;
  r.session = str(j, "session", w);
  r.driver = strOr(j, "driver", "", w);
  r.model = strOr(j, "model", "", w);
  if (j.contains("joint_names")) r.joint_names = strings(j["joint_names"], w + ".joint_names");
  r.ready = boolOr(j, "ready", false, w);
  r.detail = strOr(j, "detail", "", w);
  const std::string status = strOr(j, "status", "idle", w);
  const auto parsed_status = armStatusFromName(status);
  DASH_THROW_UNLESS(parsed_status.has_value(), w + ".status: unknown status '" + status + "'");
  r.status = *parsed_status;
  r.dispatch_id = strOr(j, "dispatch_id", "", w);
  if (j.contains("result")) {
    const Json& res = j["result"];
    DASH_THROW_UNLESS(res.is_object(), w + ".result: expected an object");
    const auto code = resultCodeFromInt(static_cast<int>(int64(res, "code", w + ".result")));
    DASH_THROW_UNLESS(code.has_value(), w + ".result.code: unknown result code");
    r.result = *code;
    r.message = strOr(res, "message", "", w + ".result");
  }
  r.gripper = strOr(j, "gripper", "", w);
  if (j.contains("samples")) {
    const Json& samples = j["samples"];
    DASH_THROW_UNLESS(samples.is_array(), w + ".samples: expected an array");
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const std::string p = w + ".samples[" + std::to_string(i) + "]";
      JointSample s;
      s.t_us = int64(samples[i], "t_us", p);
      s.q = toVec(field(samples[i], "q", p), p + ".q");
      if (samples[i].contains("qd")) s.qd = toVec(samples[i]["qd"], p + ".qd");
      r.samples.push_back(s);
    }
  }
  return r;
}

std::optional<std::int64_t> parseServerTime(const std::string& text) {
  try {
    const Json j = Json::parse(text);
    if (j.is_object() && j.contains("server_time_us") && j["server_time_us"].is_number_integer()) {
      return j["server_time_us"].get<std::int64_t>();
    }
  } catch (const Json::exception&) {
  }
  return std::nullopt;
}

std::string formatSse(const std::string& event, const std::string& data) {
  return "event: " + event + "\ndata: " + data + "\n\n";
}

std::vector<SseEvent> SseParser::feed(const char* data, std::size_t size) {
  std::vector<SseEvent> out;
  buffer_.append(data, size);
  std::size_t start = 0;
  for (;;) {
    const std::size_t nl = buffer_.find('\n', start);
    if (nl == std::string::npos) break;
    std::size_t end = nl;
    if (end > start && buffer_[end - 1] == '\r') --end;
    line(buffer_.substr(start, end - start), out);
    start = nl + 1;
  }
  buffer_.erase(0, start);
  return out;
}

void SseParser::line(const std::string& text, std::vector<SseEvent>& out) {
  if (text.empty()) {  // blank line: dispatch
    if (has_data_) {
      if (current_.event.empty()) current_.event = "message";
      out.push_back(current_);
    }
    current_ = SseEvent{};
    has_data_ = false;
    return;
  }
  if (text[0] == ':') return;  // comment (heartbeat)
  const std::size_t colon = text.find(':');
  std::string name = text.substr(0, colon);
  std::string value = colon == std::string::npos ? "" : text.substr(colon + 1);
  if (!value.empty() && value[0] == ' ') value.erase(0, 1);
  if (name == "event") {
    current_.event = value;
  } else if (name == "data") {
    if (has_data_) current_.data += '\n';
    current_.data += value;
    has_data_ = true;
  }
}

}  // namespace dash::dispatch
