#include "engine/dash/plan_extraction.h"

#include <algorithm>

namespace dash {

namespace {

struct Pending {
  std::vector<JointVector> path;
  std::vector<HyperarcId> arcs;
};

void append(Pending& pending, const MovePath& move, HyperarcId arc) {
  pending.arcs.push_back(arc);
  if (pending.path.empty()) {
    pending.path = move.path;
    return;
  }
  pending.path.insert(pending.path.end(), move.path.begin() + 1, move.path.end());
}

std::int16_t i16(int v) { return static_cast<std::int16_t>(v); }

}  // namespace

ExtractedPlan extractPlan(const MotionHypergraph& graph, const HyperpathResult& path) {
  const MotionGraph& g = graph.graph();
  const TaskSpace& space = graph.space();
  const TransitionCatalog& catalog = graph.catalog();
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  ExtractedPlan out;
  out.motion.status = MotionStatus::kOk;
  out.motion.robots.resize(static_cast<std::size_t>(robots));
  out.home_moves.resize(static_cast<std::size_t>(robots));
  std::vector<Pending> pending(static_cast<std::size_t>(robots));
  // The plan steps each hyperpath step (transitively, through moves) comes after.
  std::vector<std::vector<int>> produced_by(path.steps.size());

  // The approach and retreat come as back-off paths from q (q first): the approach is the reverse.
  auto visit = [&](int robot, int role, int step, const std::vector<JointVector>& pre_path, const JointVector& q,
                   const std::vector<JointVector>& post_path, const HeldObject& before, const HeldObject& after) {
    StepVisit v;
    v.step = step;
    v.receiver = role == 1;
    v.q = q;
    setApproach(v, pre_path);
    setRetreat(v, post_path);
    Pending& p = pending[robot];
    v.transit = p.path.empty() ? std::vector<JointVector>{v.q_pre} : std::move(p.path);
    v.held_before = before;
    v.held_after = after;
    out.motion.robots[robot].visits.push_back(std::move(v));
    out.step_moves[step][role] = std::move(p.arcs);
    p = {};
  };

  for (std::size_t i = 1; i + 1 < path.steps.size(); ++i) {
    const HyperpathStep& s = path.steps[i];
    const MotionArc& arc = g.property(s.hyperarc);
    std::vector<int> after;
    for (std::size_t d : s.dependsOn) after.insert(after.end(), produced_by[d].begin(), produced_by[d].end());
    std::sort(after.begin(), after.end());
    after.erase(std::unique(after.begin(), after.end()), after.end());
    if (arc.type == MotionArc::Type::kMove) {
      const MovePath& move = graph.move(arc.index);
      append(pending[move.robot], move, s.hyperarc);
      produced_by[i] = std::move(after);
      continue;
    }
    const int k = static_cast<int>(out.plan.steps.size());
    produced_by[i] = {k};
    out.step_moves.emplace_back();
    TaskStep step;
    step.arc = s.hyperarc;
    step.after = std::move(after);
    TransitionConfig tc;
    tc.sampled = true;
    switch (arc.type) {
      case MotionArc::Type::kPick:
      case MotionArc::Type::kPlace: {
        const GraspSample& gs = catalog.grasps[arc.index];
        const bool pick = arc.type == MotionArc::Type::kPick;
        step.action = TaskArc{pick ? TaskArcType::kPick : TaskArcType::kPlace, i16(gs.robot), -1, i16(gs.object),
                              i16(gs.placement), -1, gs.grasp, gs.grasp, graph.cost(s.hyperarc)};
        tc.q = gs.q;
        tc.X_WO = space.location(gs.object, gs.placement).X_WO;
        tc.X_TO = gs.held.X_TO;
        out.plan.steps.push_back(std::move(step));
        out.transitions.push_back(tc);
        if (pick)
          visit(gs.robot, 0, k, gs.pre_path, gs.q, gs.hold_path, HeldObject{}, gs.held);
        else
          visit(gs.robot, 0, k, gs.hold_path, gs.q, gs.pre_path, gs.held, HeldObject{});
        break;
      }
      case MotionArc::Type::kHandover: {
        const HandoverSample& h = catalog.handovers[arc.index];
        step.action = TaskArc{TaskArcType::kHandover, i16(h.giver), i16(h.receiver), i16(h.object), -1, -1, h.grasp,
                              h.grasp2, graph.cost(s.hyperarc)};
        tc.q = h.q1;
        tc.q2 = h.q2;
        tc.X_WO = h.X_WO;
        tc.X_TO = h.held.X_TO;
        tc.X_TO2 = h.held2.X_TO;
        out.plan.steps.push_back(std::move(step));
        out.transitions.push_back(tc);
        visit(h.giver, 0, k, {h.q1}, h.q1, h.q1_post_path, h.held, HeldObject{});
        visit(h.receiver, 1, k, h.q2_pre_path, h.q2, h.q2_post_path, HeldObject{}, h.held2);
        break;
      }
      case MotionArc::Type::kInspect: {
        const InspectSample& is = catalog.inspects[arc.index];
        step.action = TaskArc{TaskArcType::kInspect, i16(is.robot), -1,
                              i16(scene.tasks[is.task].requires_removed_object), i16(arc.extra), i16(is.task),
                              GraspClass::kTop, GraspClass::kTop, graph.cost(s.hyperarc)};
        tc.q = is.q;
        tc.X_WO = scene.tasks[is.task].X_WT;
        out.plan.steps.push_back(std::move(step));
        out.transitions.push_back(tc);
        visit(is.robot, 0, k, is.pre_path, is.q, is.pre_path, HeldObject{}, HeldObject{});
        break;
      }
      default:
        DASH_DEMAND_MSG(false, "a hyperpath step between source and sink is a move or a transition");
    }
  }
  for (int r = 0; r < robots; ++r) {
    out.motion.robots[r].home_path = std::move(pending[r].path);
    out.home_moves[r] = std::move(pending[r].arcs);
  }
  return out;
}

}  // namespace dash
