#include "engine/plan/plan_validator.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "engine/core/check.h"
#include "engine/plan/certified_geometry.h"
#include "engine/plan/validation_geometry.h"
#include "engine/plan/validation_timeline.h"

namespace dash {

const char* problemKindName(ProblemKind kind) {
  switch (kind) {
    case ProblemKind::kFormat: return "format";
    case ProblemKind::kStatus: return "status";
    case ProblemKind::kSceneName: return "scene_name";
    case ProblemKind::kMakespan: return "makespan";
    case ProblemKind::kRobotMissing: return "robot_missing";
    case ProblemKind::kRobotUnknown: return "robot_unknown";
    case ProblemKind::kJointNames: return "joint_names";
    case ProblemKind::kTimeOrder: return "time_order";
    case ProblemKind::kStartTime: return "start_time";
    case ProblemKind::kStartHome: return "start_home";
    case ProblemKind::kJointLimit: return "joint_limit";
    case ProblemKind::kVelocity: return "velocity";
    case ProblemKind::kEndHome: return "end_home";
    case ProblemKind::kEventReference: return "event_reference";
    case ProblemKind::kCapability: return "capability";
    case ProblemKind::kFixedObject: return "fixed_object";
    case ProblemKind::kGraspPose: return "grasp_pose";
    case ProblemKind::kGraspHeld: return "grasp_held";
    case ProblemKind::kHandsFull: return "hands_full";
    case ProblemKind::kHandover: return "handover";
    case ProblemKind::kReleaseNotHeld: return "release_not_held";
    case ProblemKind::kReleaseUnstable: return "release_unstable";
    case ProblemKind::kInspectPose: return "inspect_pose";
    case ProblemKind::kInspectNotRemoved: return "inspect_not_removed";
    case ProblemKind::kSelfCollision: return "self_collision";
    case ProblemKind::kRobotRobotCollision: return "robot_robot_collision";
    case ProblemKind::kRobotObstacleCollision: return "robot_obstacle_collision";
    case ProblemKind::kRobotObjectCollision: return "robot_object_collision";
    case ProblemKind::kHeldObjectCollision: return "held_object_collision";
    case ProblemKind::kObjectObjectCollision: return "object_object_collision";
    case ProblemKind::kHeldAtEnd: return "held_at_end";
    case ProblemKind::kGoalNotReached: return "goal_not_reached";
    case ProblemKind::kTaskMissing: return "task_missing";
  }
  return "unknown";
}

bool ValidationReport::has(ProblemKind kind) const { return count(kind) > 0; }

int ValidationReport::count(ProblemKind kind) const {
  return static_cast<int>(std::count_if(problems.begin(), problems.end(), [&](const ValidationProblem& p) { return p.kind == kind; }));
}

std::string ValidationReport::summary() const {
  std::ostringstream out;
  for (const auto& p : problems) {
    out << "t=" << validation::formatNumber(p.t, 6) << " " << problemKindName(p.kind);
    if (!p.robot.empty()) out << " " << p.robot;
    if (!p.object.empty()) out << " " << p.object;
    out << ": " << p.message << "\n";
  }
  return out.str();
}

namespace {

using validation::formatNumber;

constexpr double kMaxClearance = 0.1;
/// A finer floor multiplies the distance queries near every contact; a coarser one certifies nothing.
constexpr double kMinCertifyFloor = 1e-6;
constexpr double kMaxCertifyFloor = 0.01;

class Checks {
 public:
  Checks(const Scene& scene, const Plan& plan, const ValidationOptions& options, ValidationReport& report)
      : scene_(scene), plan_(plan), options_(options), report_(report) {}

  void add(ProblemKind kind, double t, const std::string& robot, const std::string& object, const std::string& message) {
    report_.problems.push_back({.kind = kind, .t = t, .t_end = t, .robot = robot, .object = object, .other = "", .message = message});
  }

  void header() {
    if (plan_.format != kPlanFormat) {
      add(ProblemKind::kFormat, 0.0, "", "", "format is \"" + plan_.format + "\", expected \"" + kPlanFormat + "\"");
    }
    if (plan_.status != kPlanStatusSolved) {
      add(ProblemKind::kStatus, 0.0, "", "", "status is \"" + plan_.status + "\", expected \"" + kPlanStatusSolved + "\"");
    }
    if (plan_.scene != scene_.name) {
      add(ProblemKind::kSceneName, 0.0, "", "", "the plan is for scene \"" + plan_.scene + "\", not \"" + scene_.name + "\"");
    }
    for (const PlanEvent& e : plan_.events) {
      if (!(e.t >= 0.0)) add(ProblemKind::kTimeOrder, 0.0, e.robot, e.object, std::string(eventTypeName(e.type)) + " event before t=0");
    }
    const double last = plan_.lastTime();
    if (!(std::abs(plan_.makespan - last) <= options_.time_tolerance)) {
      add(ProblemKind::kMakespan, last, "", "",
          "makespan is " + formatNumber(plan_.makespan, 9) + " but the last point or event is at t=" + formatNumber(last, 9));
    }
  }

  void trajectories() {
    std::set<std::string> seen;
    for (const RobotTrajectory& traj : plan_.robots) {
      if (!seen.insert(traj.robot).second) {
        add(ProblemKind::kRobotUnknown, 0.0, traj.robot, "", "robot " + traj.robot + " is listed twice");
        continue;
      }
      const int r = scene_.robotIndex(traj.robot);
      if (r < 0) {
        add(ProblemKind::kRobotUnknown, 0.0, traj.robot, "", "robot " + traj.robot + " is not in the scene");
        continue;
      }
      trajectory(scene_.robots[static_cast<std::size_t>(r)], traj);
    }
    for (const SceneRobot& robot : scene_.robots) {
      if (plan_.findRobot(robot.id) == nullptr) {
        add(ProblemKind::kRobotMissing, 0.0, robot.id, "", "robot " + robot.id + " has no trajectory (every scene robot must have one)");
      }
    }
  }

  void endState(const validation::Timeline& timeline, const validation::PlanMotion& motion) {
    const validation::Epoch& last = timeline.epochs.back();
    const double t_end = std::max(plan_.lastTime(), last.t);
    for (std::size_t j = 0; j < scene_.objects.size(); ++j) {
      const SceneObject& object = scene_.objects[j];
      const validation::ObjectState& s = last.objects[j];
      if (s.held()) {
        const std::string& robot = scene_.robots[static_cast<std::size_t>(s.holders.front().robot)].id;
        add(ProblemKind::kHeldAtEnd, t_end, robot, object.id, object.id + " is still held by " + robot + " at the end of the plan");
      }
      if (!object.X_WO_goal) continue;
      const Pose X_WO = validation::objectPose(last, static_cast<int>(j), motion, t_end);
      const double dp = translationDistance(X_WO, *object.X_WO_goal);
      const double dr = rotationDistance(X_WO, *object.X_WO_goal);
      if (dp > options_.goal_position_tolerance || dr > options_.goal_rotation_tolerance) {
        add(ProblemKind::kGoalNotReached, t_end, "", object.id,
            object.id + " ends " + formatNumber(dp * 1000.0) + " mm and " + formatNumber(dr) + " rad from its goal (allowed " +
                formatNumber(options_.goal_position_tolerance * 1000.0) + " mm, " +
                formatNumber(options_.goal_rotation_tolerance) + " rad)");
      }
    }
    for (std::size_t k = 0; k < scene_.tasks.size(); ++k) {
      if (timeline.task_mentioned[k] != 0) continue;  // an illegal inspect of it is reported already
      add(ProblemKind::kTaskMissing, t_end, "", scene_.tasks[k].target,
          "task " + std::to_string(k) + " (inspect " + scene_.tasks[k].target + ") has no inspect event");
    }
  }

 private:
  static std::string joint(const RobotModel& model, int i) { return model.joint_names[static_cast<std::size_t>(i)]; }

  void trajectory(const SceneRobot& robot, const RobotTrajectory& traj) {
    const RobotModel& model = *robot.model;
    if (traj.joint_names != model.joint_names) {
      std::string expected;
      for (const auto& name : model.joint_names) expected += (expected.empty() ? "" : ", ") + name;
      add(ProblemKind::kJointNames, 0.0, robot.id, "",
          robot.id + ": joint_names do not match the " + model.name + " model (expected " + expected + ", in order)");
      if (static_cast<int>(traj.joint_names.size()) != model.dof()) return;  // the points cannot be read
    }
    const auto& points = traj.points;
    if (points.empty()) {
      add(ProblemKind::kStartTime, 0.0, robot.id, "", robot.id + ": the trajectory has no points (it must start at t=0 at home)");
      return;
    }
    if (!(std::abs(points.front().t) <= options_.time_tolerance)) {
      add(ProblemKind::kStartTime, points.front().t, robot.id, "",
          robot.id + ": the first point is at t=" + formatNumber(points.front().t, 9) + ", not at t=0");
    }
    const double start_error = (points.front().q - robot.home).cwiseAbs().maxCoeff();
    if (start_error > options_.home_tolerance) {
      add(ProblemKind::kStartHome, points.front().t, robot.id, "",
          robot.id + ": the first point is " + formatNumber(start_error) + " from home in some joint (allowed " +
              formatNumber(options_.home_tolerance) + ")");
    }
    for (std::size_t k = 0; k < points.size(); ++k) {
      const TrajectoryPoint& p = points[k];
      for (int i = 0; i < model.dof(); ++i) {
        const double lo = model.limits.position_min[i] - options_.limit_tolerance;
        const double hi = model.limits.position_max[i] + options_.limit_tolerance;
        if (p.q[i] < lo || p.q[i] > hi) {
          add(ProblemKind::kJointLimit, p.t, robot.id, "",
              robot.id + ": point " + std::to_string(k) + " puts " + joint(model, i) + " at " + formatNumber(p.q[i], 6) +
                  ", outside [" + formatNumber(model.limits.position_min[i], 6) + ", " +
                  formatNumber(model.limits.position_max[i], 6) + "]");
        }
      }
      if (k == 0) continue;
      const TrajectoryPoint& prev = points[k - 1];
      const double dt = p.t - prev.t;
      if (!(dt > 0.0)) {
        add(ProblemKind::kTimeOrder, p.t, robot.id, "",
            robot.id + ": point " + std::to_string(k) + " at t=" + formatNumber(p.t, 9) + " does not come after point " +
                std::to_string(k - 1) + " at t=" + formatNumber(prev.t, 9));
        continue;
      }
      velocity(robot, k, prev, p, dt);
    }
    if (scene_.end_at_home) {
      const double end_error = (points.back().q - robot.home).cwiseAbs().maxCoeff();
      if (end_error > options_.home_tolerance) {
        add(ProblemKind::kEndHome, points.back().t, robot.id, "",
            robot.id + ": the last point is " + formatNumber(end_error) + " from home in some joint (the scene requires ending at home)");
      }
    }
  }

  void velocity(const SceneRobot& robot, std::size_t k, const TrajectoryPoint& a, const TrajectoryPoint& b, double dt) {
    const RobotModel& model = *robot.model;
    int worst = -1;
    double worst_ratio = 1.0 + options_.velocity_tolerance;
    for (int i = 0; i < model.dof(); ++i) {
      const double ratio = std::abs(b.q[i] - a.q[i]) / dt / model.limits.velocity_max[i];
      if (ratio > worst_ratio) {
        worst_ratio = ratio;
        worst = i;
      }
    }
    if (worst < 0) return;
    const double speed = std::abs(b.q[worst] - a.q[worst]) / dt;
    add(ProblemKind::kVelocity, a.t, robot.id, "",
        robot.id + ": between points " + std::to_string(k - 1) + " and " + std::to_string(k) + " (t=" + formatNumber(a.t, 6) +
            " to " + formatNumber(b.t, 6) + ") " + joint(model, worst) + " moves at " + formatNumber(speed) + ", over its limit " +
            formatNumber(model.limits.velocity_max[worst]));
  }

  const Scene& scene_;
  const Plan& plan_;
  const ValidationOptions& options_;
  ValidationReport& report_;
};

}  // namespace

ValidationReport validatePlan(const Scene& scene, const Plan& plan, const ValidationOptions& options) {
  DASH_THROW_UNLESS(std::isfinite(options.clearance) && options.clearance >= 0.0 && options.clearance <= kMaxClearance,
                    "validation clearance must be between 0 and 0.1 m");
  DASH_THROW_UNLESS(options.certify_floor >= kMinCertifyFloor && options.certify_floor <= kMaxCertifyFloor,
                    "certify_floor must be between 1e-6 and 0.01 m");
  ValidationReport report;
  Checks checks(scene, plan, options, report);
  checks.header();
  checks.trajectories();
  const validation::PlanMotion motion(scene, plan);
  const validation::Timeline timeline = validation::replayEvents(plan, motion, options, report.problems);
  if (options.geometry == ValidationOptions::GeometryCheck::kCertified) {
    validation::checkGeometryCertified(plan, motion, timeline, options, report);
  } else {
    validation::checkGeometry(plan, motion, timeline, options, report);
  }
  checks.endState(timeline, motion);
  std::stable_sort(report.problems.begin(), report.problems.end(),
                   [](const ValidationProblem& a, const ValidationProblem& b) { return a.t < b.t; });
  return report;
}

}  // namespace dash
