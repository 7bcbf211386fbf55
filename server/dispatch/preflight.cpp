#include "server/dispatch/preflight.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "engine/plan/plan_validator.h"

namespace dash::dispatch {

namespace {

constexpr int kBadPlan = 422;
constexpr int kArmsNotReady = 409;
constexpr int kSummaryLines = 3;

std::string fmt(double v, int decimals = 3) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
  return buffer;
}

std::string firstLines(const std::string& text, int lines) {
  std::istringstream in(text);
  std::string line, out;
  int n = 0, total = 0;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    ++total;
    if (n < lines) {
      out += (n > 0 ? "; " : "") + line;
      ++n;
    }
  }
  if (total > n) out += " (and " + std::to_string(total - n) + " more)";
  return out;
}

const ControllerInfo* findController(const std::vector<ControllerInfo>& controllers, const std::string& robot) {
  for (const ControllerInfo& c : controllers) {
    if (c.robot == robot) return &c;
  }
  return nullptr;
}

std::string joinNames(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ",") + n;
  return "[" + out + "]";
}

class Checker {
 public:
  explicit Checker(PreflightReport& report) : report_(report) {}
  void fail(const std::string& name, const std::string& robot, const std::string& message, int status) {
    report_.passed = false;
    report_.checks.push_back({name, robot, false, message, status});
  }
  void pass(const std::string& name, const std::string& robot, const std::string& message = "") {
    report_.checks.push_back({name, robot, true, message, 200});
  }

 private:
  PreflightReport& report_;
};

/// Time order and speeds of one robot's trajectory; returns false if the times are unusable.
bool checkTimesAndSpeeds(const RobotTrajectory& rt, const RobotModel& model, const ArmTrajectory& arm,
                         const PreflightOptions& options, Checker& checker) {
  bool times_ok = !rt.points.empty() && std::abs(rt.points.front().t) <= 1e-9;
  std::string time_problem = rt.points.empty() ? "no points" : "the first point is at t=" + fmt(rt.points.front().t);
  for (std::size_t i = 1; times_ok && i < rt.points.size(); ++i) {
    if (!(rt.points[i].t > rt.points[i - 1].t)) {
      times_ok = false;
      time_problem = "point " + std::to_string(i) + " (t=" + fmt(rt.points[i].t) + ") does not come after point " +
                     std::to_string(i - 1) + " (t=" + fmt(rt.points[i - 1].t) + ")";
    }
  }
  if (!times_ok) {
    checker.fail("time_order", rt.robot, "times must start at 0 and strictly increase: " + time_problem, kBadPlan);
    return false;
  }
  checker.pass("time_order", rt.robot);

  const JointVector& vmax = model.limits.velocity_max;
  const double allowed = 1.0 + options.velocity_tolerance;
  for (std::size_t i = 0; i + 1 < rt.points.size(); ++i) {
    const double dt = (rt.points[i + 1].t - rt.points[i].t) * options.time_scale;
    for (Eigen::Index j = 0; j < vmax.size() && j < rt.points[i].q.size(); ++j) {
      const double speed = std::abs(rt.points[i + 1].q[j] - rt.points[i].q[j]) / dt;
      if (speed > vmax[j] * allowed) {
        checker.fail("speed_limits", rt.robot,
                     "segment " + std::to_string(i) + " (t " + fmt(rt.points[i].t) + "-" + fmt(rt.points[i + 1].t) +
                         " s): " + model.joint_names[static_cast<std::size_t>(j)] + " moves at " + fmt(speed) +
                         " (limit " + fmt(vmax[j]) + ")",
                     kBadPlan);
        return true;
      }
    }
  }
  const PeakSpeed peak = peakSpeed(arm, vmax);
  if (peak.ratio > allowed) {
    const auto seg = static_cast<std::size_t>(peak.segment);
    checker.fail("speed_limits", rt.robot,
                 "segment " + std::to_string(seg) + " (t " + fmt(arm.points[seg].time_from_start) + "-" +
                     fmt(arm.points[seg + 1].time_from_start) + " s): " +
                     model.joint_names[static_cast<std::size_t>(peak.joint)] + " would reach " + fmt(peak.speed) +
                     " (limit " + fmt(vmax[peak.joint]) + ") easing into and out of the plan's corners; dispatch " +
                     "with time_scale >= " + fmt(options.time_scale * peak.ratio * (1.0 + 1e-3), 3),
                 kBadPlan);
    return true;
  }
  checker.pass("speed_limits", rt.robot, "peak " + fmt(peak.ratio * 100.0, 1) + "% of velocity_max");
  return true;
}

/// Joint names and order: the plan against the model, then the agent against both. Whether they agree.
bool checkJointNames(const RobotTrajectory& rt, const RobotModel& model, const ControllerInfo* controller,
                     Checker& checker) {
  if (rt.joint_names != model.joint_names) {
    checker.fail("joint_names", rt.robot,
                 "the plan's joint names " + joinNames(rt.joint_names) + " differ from the " + model.name +
                     " model's " + joinNames(model.joint_names),
                 kBadPlan);
    return false;
  }
  if (controller != nullptr && controller->connected && controller->joint_names != model.joint_names) {
    checker.fail("joint_names", rt.robot,
                 "the controller reports joint names " + joinNames(controller->joint_names) + ", the plan has " +
                     joinNames(rt.joint_names),
                 kArmsNotReady);
    return false;
  }
  checker.pass("joint_names", rt.robot);
  return true;
}

/// The robot's controller: connected, ready and idle, its arm at the plan's start.
void checkController(const RobotTrajectory& rt, const RobotModel& model, const ControllerInfo* controller,
                     bool names_ok, const PreflightOptions& options, Checker& checker) {
  if (controller == nullptr || !controller->connected) {
    checker.fail("controller_connected", rt.robot, "no controller agent is connected for this robot", kArmsNotReady);
    return;
  }
  checker.pass("controller_connected", rt.robot, controller->driver + " driver");
  const bool busy = controller->status == ArmStatus::kArmed || controller->status == ArmStatus::kExecuting;
  if (!controller->ready || busy) {
    checker.fail("controller_ready", rt.robot,
                 std::string("the controller is not ready") + (busy ? " (it is still running a goal)" : "") +
                     (controller->detail.empty() ? "" : ": " + controller->detail),
                 kArmsNotReady);
    return;
  }
  checker.pass("controller_ready", rt.robot);

  const auto& sample = controller->last_sample;
  const double age = sample ? (options.now_us - controller->last_report_us) * 1e-6 : INFINITY;
  if (!sample || age > options.state_timeout) {
    checker.fail("start_state", rt.robot, "no recent joint state from the controller", kArmsNotReady);
    return;
  }
  if (!names_ok || rt.points.empty() || sample->q.size() != rt.points.front().q.size()) {
    checker.fail("start_state", rt.robot, "the measured state has " + std::to_string(sample->q.size()) + " joints",
                 kArmsNotReady);
    return;
  }
  const JointVector diff = (sample->q - rt.points.front().q).cwiseAbs();
  Eigen::Index worst = 0;
  const double error = diff.maxCoeff(&worst);
  if (error > options.start_tolerance) {
    checker.fail("start_state", rt.robot,
                 "the arm is not at the plan's start: " + model.joint_names[static_cast<std::size_t>(worst)] +
                     " measured " + fmt(sample->q[worst], 4) + ", plan starts at " +
                     fmt(rt.points.front().q[worst], 4) + " (difference " + fmt(error, 4) + " > tolerance " +
                     fmt(options.start_tolerance, 4) + ")",
                 kArmsNotReady);
    return;
  }
  checker.pass("start_state", rt.robot, "within " + fmt(error, 5));
}

}  // namespace

std::string PreflightReport::reason() const {
  for (const PreflightCheck& c : checks) {
    if (!c.passed) return (c.robot.empty() ? "" : c.robot + ": ") + c.message;
  }
  return "";
}

int PreflightReport::httpStatus() const {
  if (passed) return 200;
  bool any_plan = false;
  for (const PreflightCheck& c : checks) any_plan = any_plan || (!c.passed && c.http_status == kBadPlan);
  return any_plan ? kBadPlan : kArmsNotReady;
}

PreflightReport runPreflight(const Scene& scene, const Plan& plan, const std::vector<ControllerInfo>& controllers,
                             const PreflightOptions& options) {
  PreflightReport report;
  Checker checker(report);

  ValidationOptions vopts;
  vopts.check_geometry = options.validate_geometry;
  vopts.threads = options.validator_threads;
  const ValidationReport validation = validatePlan(scene, plan, vopts);
  if (validation.valid()) {
    checker.pass("plan_valid", "", std::to_string(validation.samples) + " instants checked");
  } else {
    checker.fail("plan_valid", "",
                 "the plan does not pass the plan validator: " + firstLines(validation.summary(), kSummaryLines),
                 kBadPlan);
  }
  if (plan.robots.empty()) checker.fail("plan_valid", "", "the plan has no robots", kBadPlan);

  for (const RobotTrajectory& rt : plan.robots) {
    const int scene_index = scene.robotIndex(rt.robot);
    if (scene_index < 0) {
      checker.fail("plan_valid", rt.robot, "the scene has no robot '" + rt.robot + "'", kBadPlan);
      continue;
    }
    const SceneRobot& sr = scene.robots[static_cast<std::size_t>(scene_index)];
    const RobotModel& model = *sr.model;
    const ControllerInfo* controller = findController(controllers, rt.robot);
    const bool names_ok = checkJointNames(rt, model, controller, checker);
    ArmTrajectory arm = armTrajectoryFromPlan(plan, rt.robot, options.time_scale);
    const bool times_ok = checkTimesAndSpeeds(rt, model, arm, options, checker);
    (void)times_ok;
    report.trajectories.push_back(std::move(arm));
    checkController(rt, model, controller, names_ok, options, checker);
  }
  return report;
}

}  // namespace dash::dispatch
