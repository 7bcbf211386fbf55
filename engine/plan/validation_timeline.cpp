#include "engine/plan/validation_timeline.h"

#include <algorithm>
#include <numeric>
#include <sstream>

#include "engine/robots/kinematics.h"
#include "engine/scene/support.h"

namespace dash::validation {

std::string formatNumber(double x, int digits) {
  std::ostringstream out;
  out.precision(digits);
  out << x;
  return out.str();
}

PlanMotion::PlanMotion(const Scene& scene, const Plan& plan) : scene_(&scene) {
  trajectories_.assign(scene.robots.size(), nullptr);
  for (std::size_t r = 0; r < scene.robots.size(); ++r) {
    const RobotTrajectory* traj = plan.findRobot(scene.robots[r].id);
    if (traj == nullptr || traj->points.empty()) continue;
    const int dof = scene.robots[r].model->dof();
    const bool sized = std::all_of(traj->points.begin(), traj->points.end(),
                                   [&](const TrajectoryPoint& p) { return p.q.size() == dof; });
    if (sized) trajectories_[r] = traj;
  }
}

JointVector PlanMotion::q(int r, double t) const {
  const RobotTrajectory* traj = trajectory(r);
  // Times before 0 only come from malformed plans built in code (reported as time_order): read them as 0.
  return traj == nullptr ? scene_->robots[static_cast<std::size_t>(r)].home : traj->positionAt(std::max(t, 0.0));
}

Pose PlanMotion::tcp(int r, double t) const {
  const SceneRobot& robot = scene_->robots[static_cast<std::size_t>(r)];
  return forwardKinematics(*robot.model, robot.X_WB, q(r, t)).X_WT;
}

int Timeline::indexAt(double t) const {
  const auto after = std::upper_bound(epochs.begin(), epochs.end(), t, [](double time, const Epoch& e) { return time < e.t; });
  return after == epochs.begin() ? 0 : static_cast<int>(after - epochs.begin()) - 1;
}

const Epoch& Timeline::at(double t) const { return epochs[static_cast<std::size_t>(indexAt(t))]; }

Pose objectPose(const Epoch& epoch, int object, const PlanMotion& motion, double t) {
  const ObjectState& s = epoch.objects[static_cast<std::size_t>(object)];
  if (!s.held()) return s.X_WO;
  return motion.tcp(s.holders.front().robot, t) * s.holders.front().X_TO;
}

namespace {

/// Replays events one at a time on a mutable state.
class Replayer {
 public:
  Replayer(const PlanMotion& motion, const ValidationOptions& options, std::vector<ValidationProblem>& problems)
      : scene_(motion.scene()), motion_(motion), options_(options), problems_(problems) {
    epoch_.objects.resize(scene_.objects.size());
    for (std::size_t j = 0; j < scene_.objects.size(); ++j) epoch_.objects[j].X_WO = scene_.objects[j].X_WO_start;
    task_done_.assign(scene_.tasks.size(), 0);
    task_mentioned_.assign(scene_.tasks.size(), 0);
  }

  /// Order of events at one instant: receiving grasps of a handover, releases, other grasps, inspects.
  int phase(const PlanEvent& e) const {
    switch (e.type) {
      case PlanEvent::Type::kGrasp: {
        const int j = scene_.objectIndex(e.object);
        if (j < 0) return 2;
        const auto& holders = epoch_.objects[static_cast<std::size_t>(j)].holders;
        const int r = scene_.robotIndex(e.robot);
        const bool other_holds = std::any_of(holders.begin(), holders.end(), [&](const Holder& h) { return h.robot != r; });
        return other_holds ? 0 : 2;
      }
      case PlanEvent::Type::kRelease:
        return 1;
      case PlanEvent::Type::kInspect:
        return 3;
    }
    return 3;
  }

  void apply(const PlanEvent& e) {
    const int r = scene_.robotIndex(e.robot);
    if (r < 0) {
      problem(ProblemKind::kEventReference, e, "", std::string(eventTypeName(e.type)) + " by unknown robot \"" + e.robot + "\"");
      return;
    }
    switch (e.type) {
      case PlanEvent::Type::kGrasp:
        grasp(e, r);
        break;
      case PlanEvent::Type::kRelease:
        release(e, r);
        break;
      case PlanEvent::Type::kInspect:
        inspect(e, r);
        break;
    }
  }

  Epoch snapshot(double t) {
    Epoch e = epoch_;
    e.t = t;
    e.layout = ObjectLayout::atStart(scene_);
    for (std::size_t j = 0; j < e.objects.size(); ++j) {
      if (e.objects[j].held()) {
        e.layout.remove(static_cast<int>(j));
      } else {
        e.layout.place(static_cast<int>(j), e.objects[j].X_WO);
      }
    }
    return e;
  }

  std::vector<std::uint8_t> taskDone() const { return task_done_; }
  std::vector<std::uint8_t> taskMentioned() const { return task_mentioned_; }

 private:
  void problem(ProblemKind kind, const PlanEvent& e, const std::string& other, const std::string& message) {
    problems_.push_back({.kind = kind, .t = e.t, .t_end = e.t, .robot = e.robot, .object = e.object,
                         .other = other, .message = message});
  }

  int objectOf(const PlanEvent& e) {
    const int j = scene_.objectIndex(e.object);
    if (j < 0) {
      problem(ProblemKind::kEventReference, e, "", std::string(eventTypeName(e.type)) + " of unknown object \"" + e.object + "\"");
    }
    return j;
  }

  int heldBy(int r) const {
    for (std::size_t j = 0; j < epoch_.objects.size(); ++j) {
      for (const Holder& h : epoch_.objects[j].holders) {
        if (h.robot == r) return static_cast<int>(j);
      }
    }
    return -1;
  }

  void grasp(const PlanEvent& e, int r) {
    const int j = objectOf(e);
    if (j < 0) return;
    const SceneRobot& robot = scene_.robots[static_cast<std::size_t>(r)];
    const SceneObject& object = scene_.objects[static_cast<std::size_t>(j)];
    ObjectState& state = epoch_.objects[static_cast<std::size_t>(j)];
    if (!robot.hasCapability("grasp")) {
      problem(ProblemKind::kCapability, e, "", robot.id + " grasps " + object.id + " without the \"grasp\" capability");
    }
    if (object.fixed) problem(ProblemKind::kFixedObject, e, "", robot.id + " grasps " + object.id + ", which is fixed");
    const int holding = heldBy(r);
    if (holding == j) {
      problem(ProblemKind::kGraspHeld, e, "", robot.id + " grasps " + object.id + ", which it already holds");
      return;
    }
    if (holding >= 0) {
      problem(ProblemKind::kHandsFull, e, scene_.objects[static_cast<std::size_t>(holding)].id,
              robot.id + " grasps " + object.id + " while it still holds " + scene_.objects[static_cast<std::size_t>(holding)].id);
      return;
    }
    if (state.holders.size() >= 2) {
      problem(ProblemKind::kGraspHeld, e, "",
              robot.id + " grasps " + object.id + ", which two robots already hold (a handover takes one giver and one receiver)");
      return;
    }
    // The grasp must match where the object is now (resting, or carried by the giver of a handover).
    const Pose X_WT = motion_.tcp(r, e.t);
    const Pose X_WO = state.held() ? motion_.tcp(state.holders.front().robot, e.t) * state.holders.front().X_TO : state.X_WO;
    const Pose X_TO_actual = X_WT.inverse() * X_WO;
    const double dp = translationDistance(X_TO_actual, e.X_TO);
    const double dr = rotationDistance(X_TO_actual, e.X_TO);
    if (dp > options_.grasp_position_tolerance || dr > options_.grasp_rotation_tolerance) {
      problem(ProblemKind::kGraspPose, e, "",
              robot.id + " grasps " + object.id + " with X_TO off by " + formatNumber(dp * 1000.0) + " mm and " +
                  formatNumber(dr) + " rad from the TCP-to-object pose at that instant (allowed " +
                  formatNumber(options_.grasp_position_tolerance * 1000.0) + " mm, " +
                  formatNumber(options_.grasp_rotation_tolerance) + " rad)");
    }
    if (!state.held()) state.X_WO = X_WO;
    state.holders.push_back({r, e.X_TO});
  }

  void release(const PlanEvent& e, int r) {
    const int j = objectOf(e);
    if (j < 0) return;
    const SceneRobot& robot = scene_.robots[static_cast<std::size_t>(r)];
    const SceneObject& object = scene_.objects[static_cast<std::size_t>(j)];
    ObjectState& state = epoch_.objects[static_cast<std::size_t>(j)];
    const auto it = std::find_if(state.holders.begin(), state.holders.end(), [&](const Holder& h) { return h.robot == r; });
    if (it == state.holders.end()) {
      problem(ProblemKind::kReleaseNotHeld, e, "", robot.id + " releases " + object.id + ", which it does not hold");
      return;
    }
    const Pose X_WO = motion_.tcp(r, e.t) * it->X_TO;
    state.holders.erase(it);
    if (state.held()) return;  // a handover: the receiver carries on
    state.X_WO = X_WO;
    ObjectLayout layout = snapshot(e.t).layout;
    layout.remove(j);
    if (!findSupport(scene_, j, X_WO, layout).found()) {
      const Vec3 p = X_WO.translation();
      problem(ProblemKind::kReleaseUnstable, e, "",
              robot.id + " releases " + object.id + " at (" + formatNumber(p.x()) + ", " + formatNumber(p.y()) + ", " +
                  formatNumber(p.z()) +
                  ") where it does not rest stably (bottom face on no surface or object top, or footprint unsupported)");
    }
  }

  void inspect(const PlanEvent& e, int r) {
    const SceneRobot& robot = scene_.robots[static_cast<std::size_t>(r)];
    if (e.task < 0 || e.task >= static_cast<int>(scene_.tasks.size())) {
      problem(ProblemKind::kEventReference, e, "",
              "inspect names task " + std::to_string(e.task) + " but the scene has " + std::to_string(scene_.tasks.size()) + " tasks");
      return;
    }
    const SceneTask& task = scene_.tasks[static_cast<std::size_t>(e.task)];
    if (e.object.empty()) {
      // Problems name the inspected object even when the event does not.
      PlanEvent named = e;
      named.object = task.target;
      inspect(named, r);
      return;
    }
    const std::string what = robot.id + " inspects task " + std::to_string(e.task) + " (" + task.target + ")";
    task_mentioned_[static_cast<std::size_t>(e.task)] = 1;
    bool legal = true;
    if (e.object != task.target) {
      problem(ProblemKind::kEventReference, e, task.target, what + " but the event names object " + e.object);
      legal = false;
    }
    if (!robot.hasCapability(task.capability)) {
      problem(ProblemKind::kCapability, e, "", what + " without the \"" + task.capability + "\" capability");
      legal = false;
    }
    const double dp = translationDistance(motion_.tcp(r, e.t), task.X_WT);
    if (dp > options_.inspect_position_tolerance) {
      problem(ProblemKind::kInspectPose, e, "",
              what + " with its TCP " + formatNumber(dp * 1000.0) + " mm from the task pose (allowed " +
                  formatNumber(options_.inspect_position_tolerance * 1000.0) + " mm)");
      legal = false;
    }
    if (task.requires_removed_object >= 0) {
      const int k = task.requires_removed_object;
      const Pose X_WO = objectPose(snapshot(e.t), k, motion_, e.t);
      const double away = translationDistance(X_WO, scene_.objects[static_cast<std::size_t>(k)].X_WO_start);
      if (!(away > options_.removed_distance)) {
        problem(ProblemKind::kInspectNotRemoved, e, *task.requires_removed,
                what + " while " + *task.requires_removed + " is only " + formatNumber(away * 1000.0) +
                    " mm from its start (must be more than " + formatNumber(options_.removed_distance * 1000.0) + " mm away)");
        legal = false;
      }
    }
    if (legal) task_done_[static_cast<std::size_t>(e.task)] = 1;
  }

  const Scene& scene_;
  const PlanMotion& motion_;
  const ValidationOptions& options_;
  std::vector<ValidationProblem>& problems_;
  Epoch epoch_;
  std::vector<std::uint8_t> task_done_;
  std::vector<std::uint8_t> task_mentioned_;
};

}  // namespace

Timeline replayEvents(const Plan& plan, const PlanMotion& motion, const ValidationOptions& options,
                      std::vector<ValidationProblem>& problems) {
  Replayer replayer(motion, options, problems);
  Timeline timeline;
  timeline.epochs.push_back(replayer.snapshot(0.0));

  std::vector<std::size_t> order(plan.events.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return plan.events[a].t < plan.events[b].t; });
  for (std::size_t begin = 0; begin < order.size();) {
    // One instant: every event within time_tolerance of the first.
    const double t = plan.events[order[begin]].t;
    std::size_t end = begin;
    while (end < order.size() && plan.events[order[end]].t - t <= options.time_tolerance) ++end;
    std::vector<std::pair<int, std::size_t>> group;  // (phase, event index), phases from the state before
    for (std::size_t k = begin; k < end; ++k) group.emplace_back(replayer.phase(plan.events[order[k]]), order[k]);
    std::stable_sort(group.begin(), group.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [phase, index] : group) replayer.apply(plan.events[index]);
    Epoch epoch = replayer.snapshot(t);
    if (timeline.epochs.back().t == t) {
      timeline.epochs.back() = std::move(epoch);
    } else {
      timeline.epochs.push_back(std::move(epoch));
    }
    begin = end;
  }
  timeline.task_done = replayer.taskDone();
  timeline.task_mentioned = replayer.taskMentioned();
  return timeline;
}

}  // namespace dash::validation
