#include "engine/plan/plan_json.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "engine/core/check.h"
#include "engine/core/json_parse.h"
#include "engine/core/json_reader.h"
#include "engine/geometry/pose_json.h"

namespace dash {

namespace {

// ordered_json keeps the file's key order, so robots stay in file order and output follows the contract.
using Json = nlohmann::ordered_json;

/// The shared field reader plus what plans add: times and poses.
class Reader : public JsonReader<Json> {
 public:
  explicit Reader(const std::string& source) : JsonReader<Json>(source, "plan") {}

  double time(const Json& value, const std::string& path) const {
    const double t = number(value, path);
    if (t < 0.0) fail(path, "time must not be negative");
    return t;
  }

  Pose pose(const Json& value, const std::string& path) const {
    requireObject(value, path);
    return readPose(*this, value, path);
  }
};

RobotTrajectory parseTrajectory(const Reader& r, const std::string& id, const Json& j, const std::string& path) {
  r.requireObject(j, path);
  RobotTrajectory traj;
  traj.robot = id;
  const std::string names_path = Reader::join(path, "joint_names");
  const Json& names = r.array(r.field(j, path, "joint_names"), names_path);
  if (names.empty()) r.fail(names_path, "must not be empty");
  for (std::size_t i = 0; i < names.size(); ++i) {
    traj.joint_names.push_back(r.nonEmptyString(names[i], Reader::index(names_path, i)));
  }
  constexpr std::size_t kMaxJoints = 6;  // JointVector's inline capacity
  if (traj.joint_names.size() > kMaxJoints) {
    r.fail(names_path, "at most " + std::to_string(kMaxJoints) + " joints, got " + std::to_string(names.size()));
  }
  const std::string points_path = Reader::join(path, "points");
  const Json& points = r.array(r.field(j, path, "points"), points_path);
  if (points.empty()) r.fail(points_path, "must hold at least one point");
  traj.points.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string p_path = Reader::index(points_path, i);
    r.requireObject(points[i], p_path);
    TrajectoryPoint point;
    point.t = r.time(r.field(points[i], p_path, "t"), Reader::join(p_path, "t"));
    const auto q = r.numbers(r.field(points[i], p_path, "q"), Reader::join(p_path, "q"), traj.joint_names.size());
    point.q = JointVector::Map(q.data(), static_cast<Eigen::Index>(q.size()));
    traj.points.push_back(std::move(point));
  }
  return traj;
}

PlanEvent parseEvent(const Reader& r, const Json& j, const std::string& path) {
  r.requireObject(j, path);
  PlanEvent e;
  e.t = r.time(r.field(j, path, "t"), Reader::join(path, "t"));
  const std::string type_path = Reader::join(path, "type");
  const std::string type = r.string(r.field(j, path, "type"), type_path);
  e.robot = r.nonEmptyString(r.field(j, path, "robot"), Reader::join(path, "robot"));
  const std::string object_path = Reader::join(path, "object");
  if (type == "grasp") {
    e.type = PlanEvent::Type::kGrasp;
    e.object = r.nonEmptyString(r.field(j, path, "object"), object_path);
    e.X_TO = r.pose(r.field(j, path, "X_TO"), Reader::join(path, "X_TO"));
  } else if (type == "release") {
    e.type = PlanEvent::Type::kRelease;
    e.object = r.nonEmptyString(r.field(j, path, "object"), object_path);
  } else if (type == "inspect") {
    e.type = PlanEvent::Type::kInspect;
    const std::string task_path = Reader::join(path, "task");
    const Json& task = r.field(j, path, "task");
    if (!task.is_number_integer()) r.fail(task_path, "expected a task index (an integer)");
    if (task.is_number_unsigned()) {
      const auto index = task.get<std::uint64_t>();
      if (index > static_cast<std::uint64_t>(std::numeric_limits<int>::max())) r.fail(task_path, "task index too large");
      e.task = static_cast<int>(index);
    } else {
      r.fail(task_path, "task index must not be negative");
    }
    if (const auto it = j.find("object"); it != j.end() && !it->is_null()) e.object = r.nonEmptyString(*it, object_path);
  } else {
    r.fail(type_path, "unknown event type \"" + type + "\" (expected grasp, release or inspect)");
  }
  return e;
}

// ---- writing ----

Json poseJson(const Pose& X) {
  const Vec3 p = X.translation();
  const auto q = quatXYZW(X);
  return Json{{"p", {p.x(), p.y(), p.z()}}, {"q", {q[0], q[1], q[2], q[3]}}};
}

Json vectorJson(const JointVector& q) {
  Json out = Json::array();
  for (Eigen::Index i = 0; i < q.size(); ++i) out.push_back(q[i]);
  return out;
}

}  // namespace

Plan parsePlan(const std::string& json_text, const std::string& source_name) {
  const Reader r(source_name);
  const Json root = parseJsonText(r, json_text);
  r.requireObject(root, "");
  Plan plan;
  plan.format = r.string(r.field(root, "", "format"), "format");
  if (plan.format != kPlanFormat) {
    r.fail("format", "unknown format \"" + plan.format + "\" (expected \"" + kPlanFormat + "\")");
  }
  plan.scene = r.nonEmptyString(r.field(root, "", "scene"), "scene");
  plan.planner = r.nonEmptyString(r.field(root, "", "planner"), "planner");
  plan.status = r.nonEmptyString(r.field(root, "", "status"), "status");
  plan.makespan = r.time(r.field(root, "", "makespan"), "makespan");

  const Json& robots = r.field(root, "", "robots");
  r.requireObject(robots, "robots");
  for (const auto& [id, value] : robots.items()) {
    const std::string path = Reader::join("robots", id);
    if (id.empty()) r.fail("robots", "a robot id must not be empty");
    plan.robots.push_back(parseTrajectory(r, id, value, path));
  }
  const Json& events = r.array(r.field(root, "", "events"), "events");
  plan.events.reserve(events.size());
  for (std::size_t i = 0; i < events.size(); ++i) plan.events.push_back(parseEvent(r, events[i], Reader::index("events", i)));
  // The optional temporal plan graph: kept as text here; engine/tpg checks what it says.
  if (const auto it = root.find("tpg"); it != root.end() && !it->is_null()) {
    r.requireObject(*it, "tpg");
    plan.tpg = it->dump();
  }
  return plan;
}

Plan loadPlan(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  DASH_THROW_UNLESS(in.good(), path + ": cannot open the plan file");
  std::ostringstream text;
  text << in.rdbuf();
  return parsePlan(text.str(), path);
}

std::string planToJson(const Plan& plan) {
  Json root;
  root["format"] = plan.format;
  root["scene"] = plan.scene;
  root["planner"] = plan.planner;
  root["status"] = plan.status;
  root["makespan"] = plan.makespan;
  Json robots = Json::object();
  std::set<std::string> seen;
  for (const auto& traj : plan.robots) {
    DASH_THROW_UNLESS(seen.insert(traj.robot).second, "plan lists robot \"" + traj.robot + "\" twice");
    Json points = Json::array();
    for (const auto& p : traj.points) points.push_back(Json{{"t", p.t}, {"q", vectorJson(p.q)}});
    robots[traj.robot] = Json{{"joint_names", traj.joint_names}, {"points", points}};
  }
  root["robots"] = robots;
  Json events = Json::array();
  for (const auto& e : plan.events) {
    Json j{{"t", e.t}, {"type", eventTypeName(e.type)}, {"robot", e.robot}};
    switch (e.type) {
      case PlanEvent::Type::kGrasp:
        j["object"] = e.object;
        j["X_TO"] = poseJson(e.X_TO);
        break;
      case PlanEvent::Type::kRelease:
        j["object"] = e.object;
        break;
      case PlanEvent::Type::kInspect:
        if (!e.object.empty()) j["object"] = e.object;
        j["task"] = e.task;
        break;
    }
    events.push_back(std::move(j));
  }
  root["events"] = events;
  if (!plan.tpg.empty()) {
    Json tpg = Json::parse(plan.tpg, nullptr, /*allow_exceptions=*/false);
    DASH_THROW_UNLESS(tpg.is_object(), "the plan's tpg field is not a JSON object");
    root["tpg"] = std::move(tpg);
  }
  return root.dump(1) + "\n";
}

void savePlan(const Plan& plan, const std::string& path) {
  const std::string text = planToJson(plan);
  std::ofstream out(path, std::ios::binary);
  DASH_THROW_UNLESS(out.good(), path + ": cannot open the plan file for writing");
  out << text;
  out.close();
  DASH_THROW_UNLESS(out.good(), path + ": cannot write the plan file");
}

std::string validationReportToJson(const ValidationReport& report) {
  Json root;
  root["valid"] = report.valid();
  root["samples"] = report.samples;
  Json problems = Json::array();
  for (const auto& p : report.problems) {
    Json problem{{"kind", problemKindName(p.kind)}, {"t", p.t}, {"t_end", p.t_end}, {"robot", p.robot},
                 {"object", p.object}, {"other", p.other}, {"message", p.message}};
    if (p.distance != 0.0) {
      problem["distance"] = p.distance;
      problem["t_closest"] = p.t_closest;
    }
    problems.push_back(std::move(problem));
  }
  root["problems"] = problems;
  // The smallest clearance, when the certified check measured any pair (JSON has no infinity).
  if (std::isfinite(report.closest.distance)) {
    root["closest"] = Json{{"a", report.closest.a}, {"b", report.closest.b}, {"distance", report.closest.distance},
                           {"t", report.closest.t}};
  }
  return root.dump(1) + "\n";
}

}  // namespace dash
