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

// One extraction, its steps as methods: walk the hyperpath between source and sink, joining each
// robot's moves until its next transition, which becomes a plan step with the moves as its transit.
class PlanExtractor {
 public:
  PlanExtractor(const MotionHypergraph& graph, const HyperpathResult& path)
      : graph_(graph), path_(path), space_(graph.space()), catalog_(graph.catalog()), scene_(space_.scene()),
        robots_(static_cast<int>(scene_.robots.size())), pending_(static_cast<std::size_t>(robots_)),
        produced_by_(path.steps.size()) {
    out_.motion.status = MotionStatus::kOk;
    out_.motion.robots.resize(static_cast<std::size_t>(robots_));
    out_.home_moves.resize(static_cast<std::size_t>(robots_));
  }

  ExtractedPlan run() {
    for (std::size_t i = 1; i + 1 < path_.steps.size(); ++i) addStep(i);
    for (int r = 0; r < robots_; ++r) {
      out_.motion.robots[r].home_path = std::move(pending_[r].path);
      out_.home_moves[r] = std::move(pending_[r].arcs);
    }
    return std::move(out_);
  }

 private:
  // The plan steps hyperpath step i comes after: those its dependencies produced, sorted, unique.
  std::vector<int> planStepsBefore(const HyperpathStep& s) const {
    std::vector<int> after;
    for (std::size_t d : s.dependsOn) after.insert(after.end(), produced_by_[d].begin(), produced_by_[d].end());
    std::sort(after.begin(), after.end());
    after.erase(std::unique(after.begin(), after.end()), after.end());
    return after;
  }

  void addStep(std::size_t i) {
    const HyperpathStep& s = path_.steps[i];
    const MotionArc& arc = graph_.graph().property(s.hyperarc);
    std::vector<int> after = planStepsBefore(s);
    if (arc.type == MotionArc::Type::kMove) {
      const MovePath& move = graph_.move(arc.index);
      append(pending_[move.robot], move, s.hyperarc);
      produced_by_[i] = std::move(after);
      return;
    }
    const int k = static_cast<int>(out_.plan.steps.size());
    produced_by_[i] = {k};
    out_.step_moves.emplace_back();
    TaskStep step;
    step.arc = s.hyperarc;
    step.after = std::move(after);
    TransitionConfig tc;
    tc.sampled = true;
    switch (arc.type) {
      case MotionArc::Type::kPick:
      case MotionArc::Type::kPlace:
        addGraspStep(k, s.hyperarc, arc, std::move(step), tc);
        break;
      case MotionArc::Type::kHandover:
        addHandoverStep(k, s.hyperarc, arc, std::move(step), tc);
        break;
      case MotionArc::Type::kInspect:
        addInspectStep(k, s.hyperarc, arc, std::move(step), tc);
        break;
      default:
        DASH_DEMAND_MSG(false, "a hyperpath step between source and sink is a move or a transition");
    }
  }

  void addGraspStep(int k, HyperarcId id, const MotionArc& arc, TaskStep step, TransitionConfig& tc) {
    const GraspSample& gs = catalog_.grasps[arc.index];
    const bool pick = arc.type == MotionArc::Type::kPick;
    step.action = TaskArc{pick ? TaskArcType::kPick : TaskArcType::kPlace, i16(gs.robot), -1, i16(gs.object),
                          i16(gs.placement), -1, gs.grasp, gs.grasp, graph_.cost(id)};
    tc.q = gs.q;
    tc.X_WO = space_.location(gs.object, gs.placement).X_WO;
    tc.X_TO = gs.held.X_TO;
    out_.plan.steps.push_back(std::move(step));
    out_.transitions.push_back(tc);
    if (pick)
      visit(gs.robot, 0, k, gs.pre_path, gs.q, gs.hold_path, HeldObject{}, gs.held);
    else
      visit(gs.robot, 0, k, gs.hold_path, gs.q, gs.pre_path, gs.held, HeldObject{});
  }

  void addHandoverStep(int k, HyperarcId id, const MotionArc& arc, TaskStep step, TransitionConfig& tc) {
    const HandoverSample& h = catalog_.handovers[arc.index];
    step.action = TaskArc{TaskArcType::kHandover, i16(h.giver), i16(h.receiver), i16(h.object), -1, -1, h.grasp,
                          h.grasp2, graph_.cost(id)};
    tc.q = h.q1;
    tc.q2 = h.q2;
    tc.X_WO = h.X_WO;
    tc.X_TO = h.held.X_TO;
    tc.X_TO2 = h.held2.X_TO;
    out_.plan.steps.push_back(std::move(step));
    out_.transitions.push_back(tc);
    visit(h.giver, 0, k, {h.q1}, h.q1, h.q1_post_path, h.held, HeldObject{});
    visit(h.receiver, 1, k, h.q2_pre_path, h.q2, h.q2_post_path, HeldObject{}, h.held2);
  }

  void addInspectStep(int k, HyperarcId id, const MotionArc& arc, TaskStep step, TransitionConfig& tc) {
    const InspectSample& is = catalog_.inspects[arc.index];
    step.action = TaskArc{TaskArcType::kInspect, i16(is.robot), -1,
                          i16(scene_.tasks[is.task].requires_removed_object), i16(arc.extra), i16(is.task),
                          GraspClass::kTop, GraspClass::kTop, graph_.cost(id)};
    tc.q = is.q;
    tc.X_WO = scene_.tasks[is.task].X_WT;
    out_.plan.steps.push_back(std::move(step));
    out_.transitions.push_back(tc);
    visit(is.robot, 0, k, is.pre_path, is.q, is.pre_path, HeldObject{}, HeldObject{});
  }

  // The robot's visit of plan step `step` as `role` (0: actor or giver, 1: receiver). The approach and
  // retreat come as back-off paths from q (q first): the approach is the reverse.
  void visit(int robot, int role, int step, const std::vector<JointVector>& pre_path, const JointVector& q,
             const std::vector<JointVector>& post_path, const HeldObject& before, const HeldObject& after) {
    StepVisit v;
    v.step = step;
    v.receiver = role == 1;
    v.q = q;
    setApproach(v, pre_path);
    setRetreat(v, post_path);
    Pending& p = pending_[robot];
    v.transit = p.path.empty() ? std::vector<JointVector>{v.q_pre} : std::move(p.path);
    v.held_before = before;
    v.held_after = after;
    out_.motion.robots[robot].visits.push_back(std::move(v));
    out_.step_moves[step][role] = std::move(p.arcs);
    p = {};
  }

  const MotionHypergraph& graph_;
  const HyperpathResult& path_;
  const TaskSpace& space_;
  const TransitionCatalog& catalog_;
  const Scene& scene_;
  const int robots_;
  ExtractedPlan out_;
  std::vector<Pending> pending_;
  // The plan steps each hyperpath step (transitively, through moves) comes after.
  std::vector<std::vector<int>> produced_by_;
};

}  // namespace

ExtractedPlan extractPlan(const MotionHypergraph& graph, const HyperpathResult& path) {
  return PlanExtractor(graph, path).run();
}

}  // namespace dash
