#include "engine/tpg/tpg_replay.h"

#include <algorithm>
#include <deque>
#include <random>

#include "engine/core/check.h"

namespace dash::tpg {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }
constexpr double kMinStep = 1e-9;  ///< s: points closer than this in a replay are one point

void appendPoint(RobotTrajectory& out, double t, const JointVector& q) {
  if (!out.points.empty() && t <= out.points.back().t + kMinStep) return;
  out.points.push_back({t, q});
}

}  // namespace

double Timing::makespan() const { return end.empty() ? 0.0 : *std::max_element(end.begin(), end.end()); }

Timing schedule(const Graph& graph, const std::vector<double>& wait, const std::vector<double>& stretch) {
  const std::size_t n = graph.nodes.size();
  DASH_THROW_UNLESS(wait.size() == n && stretch.size() == n, "one wait and one stretch per node");
  const auto preds = graph.predecessors();
  std::vector<std::vector<int>> succs(n);
  std::vector<int> pending(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    pending[i] = static_cast<int>(preds[i].size());
    for (int p : preds[i]) succs[at(p)].push_back(static_cast<int>(i));
  }
  Timing timing;
  timing.start.assign(n, 0.0);
  timing.end.assign(n, 0.0);
  std::deque<int> ready;
  for (std::size_t i = 0; i < n; ++i) {
    if (pending[i] == 0) ready.push_back(static_cast<int>(i));
  }
  std::size_t done = 0;
  while (!ready.empty()) {
    const int i = ready.front();
    ready.pop_front();
    ++done;
    double start = 0.0;
    for (int p : preds[at(i)]) start = std::max(start, timing.end[at(p)]);
    const Node& node = graph.nodes[at(i)];
    timing.start[at(i)] = start + std::max(wait[at(i)], 0.0);
    timing.end[at(i)] = timing.start[at(i)] + (node.t1 - node.t0) * std::max(stretch[at(i)], 1.0);
    for (int s : succs[at(i)]) {
      if (--pending[at(s)] == 0) ready.push_back(s);
    }
  }
  DASH_THROW_UNLESS(done == n, "the graph has a cycle");
  return timing;
}

Plan replayPlan(const Plan& plan, const Graph& graph, const Timing& timing) {
  Plan out = plan;
  out.tpg.clear();
  for (std::size_t r = 0; r < plan.robots.size(); ++r) {
    const RobotTrajectory& in = plan.robots[r];
    RobotTrajectory& traj = out.robots[r];
    traj.points.clear();
    for (int i : graph.armNodes(static_cast<int>(r))) {
      const Node& node = graph.nodes[at(i)];
      const double s = timing.start[at(i)];
      const double e = timing.end[at(i)];
      if (node.kind == Node::Kind::kEvent) {
        out.events[at(node.event)].t = s;
        appendPoint(traj, s, in.positionAt(node.t0));
        continue;
      }
      appendPoint(traj, s, in.positionAt(node.t0));
      const double scale = node.t1 > node.t0 ? (e - s) / (node.t1 - node.t0) : 0.0;
      for (const TrajectoryPoint& p : in.points) {
        if (p.t > node.t0 && p.t < node.t1) appendPoint(traj, s + (p.t - node.t0) * scale, p.q);
      }
      appendPoint(traj, e, in.positionAt(node.t1));
    }
    if (traj.points.empty() || traj.points.front().t > 0.0) traj.points.insert(traj.points.begin(), {0.0, in.points.front().q});
  }
  out.makespan = 0.0;
  out.makespan = out.lastTime();
  return out;
}

ReplayReport checkReplays(const Scene& scene, const Plan& plan, const Graph& graph, const ReplayOptions& options) {
  DASH_THROW_UNLESS(options.draws >= 1 && options.draws <= 100000, "draws must be within 1 .. 100000");
  DASH_THROW_UNLESS(options.max_wait >= 0.0 && options.max_wait <= 3600.0, "max_wait must be within 0 .. 3600 s");
  DASH_THROW_UNLESS(options.max_stretch >= 1.0 && options.max_stretch <= 100.0, "max_stretch must be within 1 .. 100");
  DASH_THROW_UNLESS(options.focus < static_cast<int>(graph.nodes.size()), "focus node out of range");
  ReplayReport report;
  report.planned_makespan = plan.makespan;
  const std::size_t n = graph.nodes.size();
  for (int draw = 0; draw < options.draws; ++draw) {
    std::mt19937_64 rng(options.seed * 1000003ULL + static_cast<std::uint64_t>(draw));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<double> wait(n, 0.0), stretch(n, 1.0);
    for (std::size_t i = 0; draw > 0 && i < n; ++i) {
      if (options.focus >= 0 && static_cast<int>(i) != options.focus) continue;
      if (unit(rng) < options.wait_probability) wait[i] = unit(rng) * options.max_wait;
      stretch[i] = 1.0 + unit(rng) * (options.max_stretch - 1.0);
    }
    const Timing timing = schedule(graph, wait, stretch);
    const Plan replayed = replayPlan(plan, graph, timing);
    const ValidationReport v = validatePlan(scene, replayed, options.validation);
    ++report.draws;
    const double makespan = replayed.makespan;
    report.min_makespan = draw == 0 ? makespan : std::min(report.min_makespan, makespan);
    report.max_makespan = draw == 0 ? makespan : std::max(report.max_makespan, makespan);
    if (!v.valid()) {
      if (options.on_failure) options.on_failure(draw, timing, v);
      if (report.failed++ == 0) {
        report.first_failed_draw = draw;
        report.first_problem = v.problems.front().message;
      }
    }
  }
  return report;
}

Graph withoutEdge(Graph graph, std::size_t index) {
  DASH_THROW_UNLESS(index < graph.edges.size(), "no edge " + std::to_string(index));
  graph.edges.erase(graph.edges.begin() + static_cast<std::ptrdiff_t>(index));
  return graph;
}

}  // namespace dash::tpg
