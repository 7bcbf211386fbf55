#include "server/dispatch/tpg_execution.h"

#include <algorithm>
#include <limits>

#include "engine/core/check.h"

namespace dash::dispatch {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

ArmTrajectory motionGoal(const RobotTrajectory& traj, double t0, double t1, double scale) {
  std::vector<JointVector> q{traj.positionAt(t0)};
  std::vector<double> t{0.0};
  for (const TrajectoryPoint& p : traj.points) {
    if (p.t > t0 && p.t < t1 && (p.t - t0) * scale > t.back()) {
      q.push_back(p.q);
      t.push_back((p.t - t0) * scale);
    }
  }
  const double end = std::max((t1 - t0) * scale, t.back() + 1e-6);
  q.push_back(traj.positionAt(t1));
  t.push_back(end);
  ArmTrajectory goal;
  goal.robot = traj.robot;
  goal.joint_names = traj.joint_names;
  const std::vector<JointVector> v = velocitiesForPlanPath(q, t);
  for (std::size_t i = 0; i < q.size(); ++i) goal.points.push_back({q[i], v[i], t[i]});
  return goal;
}

ArmTrajectory gripperGoal(const RobotTrajectory& traj, const PlanEvent& e) {
  ArmTrajectory goal;
  goal.robot = traj.robot;
  goal.joint_names = traj.joint_names;
  const JointVector q = traj.positionAt(e.t);
  goal.points.push_back({q, JointVector::Zero(q.size()), 0.0});
  const auto action = e.type == PlanEvent::Type::kGrasp ? GripperCommand::Action::kGrasp : GripperCommand::Action::kRelease;
  goal.gripper.push_back({0.0, action, e.object});
  return goal;
}

/// The point of the polyline through `points` nearest to q (largest joint difference).
JointVector nearestOnPath(const std::vector<TrajectoryWaypoint>& points, const JointVector& q) {
  JointVector best = points.front().positions;
  double best_d = maxAbsDifference(q, best);
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    const JointVector& a = points[i].positions;
    const JointVector d = points[i + 1].positions - a;
    const double len2 = d.squaredNorm();
    const double u = len2 > 0.0 ? std::clamp((q - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    const JointVector p = a + u * d;
    const double dist = maxAbsDifference(q, p);
    if (dist < best_d) {
      best_d = dist;
      best = p;
    }
  }
  return best;
}

}  // namespace

const char* tpgStepKindName(TpgStep::Kind kind) {
  switch (kind) {
    case TpgStep::Kind::kMotion: return "motion";
    case TpgStep::Kind::kGripper: return "gripper";
    case TpgStep::Kind::kHold: return "hold";
    case TpgStep::Kind::kInspect: return "inspect";
  }
  return "motion";
}

TpgRun::TpgRun(const Plan& plan, const tpg::Graph& graph, const std::vector<std::string>& robots, double time_scale,
               const std::string& dispatch_id) {
  std::vector<std::pair<int, int>> where(graph.nodes.size(), {-1, -1});  // node -> (arm, step)
  for (std::size_t g = 0; g < graph.robots.size(); ++g) {
    DASH_THROW_UNLESS(std::find(robots.begin(), robots.end(), graph.robots[g]) != robots.end(),
                      "the graph's robot " + graph.robots[g] + " is not dispatched");
  }
  for (int arm = 0; arm < static_cast<int>(robots.size()); ++arm) {
    const auto it = std::find(graph.robots.begin(), graph.robots.end(), robots[at(arm)]);
    DASH_THROW_UNLESS(it != graph.robots.end(), robots[at(arm)] + " is not in the plan's graph");
    const RobotTrajectory* traj = plan.findRobot(robots[at(arm)]);
    DASH_THROW_UNLESS(traj != nullptr, robots[at(arm)] + " is not in the plan");
    std::vector<TpgStep> steps;
    for (int node : graph.armNodes(static_cast<int>(it - graph.robots.begin()))) {
      const tpg::Node& n = graph.nodes[at(node)];
      TpgStep step;
      step.node = node;
      step.planned_start = n.t0 * time_scale;
      step.planned_end = n.t1 * time_scale;
      if (n.kind == tpg::Node::Kind::kEvent) {
        const PlanEvent& e = plan.events[at(n.event)];
        step.kind = e.type == PlanEvent::Type::kInspect ? TpgStep::Kind::kInspect : TpgStep::Kind::kGripper;
        if (step.kind == TpgStep::Kind::kGripper) step.goal = gripperGoal(*traj, e);
      } else if (n.moves) {
        step.goal = motionGoal(*traj, n.t0, n.t1, time_scale);
      } else {
        step.kind = TpgStep::Kind::kHold;
      }
      step.goal_id = dispatch_id + "/" + std::to_string(arm) + "." + std::to_string(steps.size());
      where[at(node)] = {arm, static_cast<int>(steps.size())};
      steps.push_back(std::move(step));
    }
    steps_.push_back(std::move(steps));
  }
  for (const tpg::Edge& e : graph.edges) {
    const auto [to_arm, to_step] = where[at(e.to)];
    steps_[at(to_arm)][at(to_step)].waits_for.push_back(where[at(e.from)]);
  }
}

int TpgRun::current(int arm) const {
  const auto& s = steps(arm);
  int k = 0;
  while (k < static_cast<int>(s.size()) && s[at(k)].state == TpgStep::State::kDone) ++k;
  return k;
}

bool TpgRun::allDone() const {
  for (int arm = 0; arm < arms(); ++arm) {
    if (!armDone(arm)) return false;
  }
  return true;
}

bool TpgRun::mayStart(int arm) const {
  const int k = current(arm);
  if (k >= static_cast<int>(steps(arm).size())) return false;
  for (const auto& [a, s] : steps(arm)[at(k)].waits_for) {
    if (steps(a)[at(s)].state != TpgStep::State::kDone) return false;
  }
  return true;
}

std::string TpgRun::waitingFor(int arm, const std::vector<std::string>& robots) const {
  const int k = current(arm);
  if (k >= static_cast<int>(steps(arm).size())) return "";
  std::string out;
  for (const auto& [a, s] : steps(arm)[at(k)].waits_for) {
    const TpgStep& other = steps(a)[at(s)];
    if (other.state == TpgStep::State::kDone) continue;
    out += (out.empty() ? "" : ", ") + robots[at(a)] + " step " + std::to_string(s) + " (" + tpgStepKindName(other.kind) + ")";
  }
  return out;
}

int TpgRun::stepOfGoal(int arm, const std::string& goal_id) const {
  const auto& s = steps(arm);
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (s[k].goal_id == goal_id) return static_cast<int>(k);
  }
  return -1;
}

JointVector TpgRun::nearestPlanned(int arm, const JointVector& q) const {
  const auto& s = steps(arm);
  const int k = current(arm);
  if (k < static_cast<int>(s.size()) && s[at(k)].state == TpgStep::State::kSent && !s[at(k)].goal.points.empty()) {
    return nearestOnPath(s[at(k)].goal.points, q);
  }
  for (int i = std::min(k, static_cast<int>(s.size())) - 1; i >= 0; --i) {
    if (!s[at(i)].goal.points.empty()) return s[at(i)].goal.points.back().positions;
  }
  for (std::size_t i = at(k); i < s.size(); ++i) {
    if (!s[i].goal.points.empty()) return s[i].goal.points.front().positions;
  }
  return {};
}

std::vector<SegmentRecord> TpgRun::records(int arm, std::int64_t start_us) const {
  std::vector<SegmentRecord> out;
  for (const TpgStep& step : steps(arm)) {
    SegmentRecord r;
    r.node = step.node;
    r.kind = tpgStepKindName(step.kind);
    r.planned_start = step.planned_start;
    r.planned_end = step.planned_end;
    if (step.start_us != 0) r.start = (step.start_us - start_us) * 1e-6;
    if (step.end_us != 0) r.end = (step.end_us - start_us) * 1e-6;
    r.q_start = step.q_start;
    r.q_end = step.q_end;
    out.push_back(std::move(r));
  }
  return out;
}

double TpgRun::allowance(const TpgStep& step, double factor, double margin, double gripper_allowance) const {
  if (step.kind == TpgStep::Kind::kGripper) return gripper_allowance + margin;
  return factor * step.goal.duration() + margin;
}

}  // namespace dash::dispatch
