// MotionLayer's representation construction (paper, "Motion Planning Layer: Representation
// Construction"): H_M for the elements of the current task plan, built before the motion query. Per
// robot and task step: motion vertices at the transition configuration task conflict detection chose
// (before and after the transition), at the approach start and at the retreat end (the TCP backed off
// along its approach axis: a straight segment, checked when the anchor is chosen, since the IK branch
// is chosen by it); transition hyperarcs (a handover is one hyperarc coupling both robots); and the
// moves between one visit's retreat end and the robot's next approach start, whose paths are not
// validated here (the straight joint segment stands in until the motion query validates a path).
// Elements already in H_M from an earlier round are the same elements (MotionHypergraph deduplicates).
#include <utility>

#include "engine/motion/motion_anchors.h"
#include "engine/robots/kinematics.h"

namespace dash {

std::string motionVertexLabel(const Scene& scene, const lazy::MotionVertex& v) {
  const TaskElement& e = v.element;
  if (e.kind == ElementKind::kTaskPending || e.kind == ElementKind::kTaskDone)
    return "task " + std::to_string(e.task) + (e.kind == ElementKind::kTaskDone ? " done" : " pending");
  if (v.robot < 0) return scene.objects[e.object].id + "@" + std::to_string(e.location);
  std::string s = scene.robots[v.robot].id;
  if (e.kind == ElementKind::kHolding)
    s += "+" + scene.objects[e.object].id + " (" + graspClassName(e.grasp) + ")";
  return s;
}

namespace {

struct Roles {
  HeldObject before;
  HeldObject after;
};

Roles heldAround(const TaskArc& a, const TransitionConfig& tc, bool receiver) {
  switch (a.type) {
    case TaskArcType::kPick:
      return {{}, {a.object, tc.X_TO}};
    case TaskArcType::kPlace:
      return {{a.object, tc.X_TO}, {}};
    case TaskArcType::kHandover:
      return receiver ? Roles{{}, {a.object, tc.X_TO2}} : Roles{{a.object, tc.X_TO}, {}};
    default:
      return {};
  }
}

/// The task element robot r is in before and after its part in action a.
std::pair<TaskElement, TaskElement> elementsAround(const TaskArc& a, int r) {
  const TaskElement alone = TaskElement::robotAlone(r);
  switch (a.type) {
    case TaskArcType::kPick:
      return {alone, TaskElement::holding(r, a.object, a.grasp)};
    case TaskArcType::kPlace:
      return {TaskElement::holding(r, a.object, a.grasp), alone};
    case TaskArcType::kHandover:
      return r == a.robot ? std::pair{TaskElement::holding(r, a.object, a.grasp), alone}
                          : std::pair{alone, TaskElement::holding(r, a.object, a.grasp2)};
    default:
      return {alone, alone};
  }
}

/// What the giver of a handover did, for the receiver that follows it in the same step.
struct GiverState {
  bool backs_off = true;
  JointVector q_post;
  Vec3 approach_W = Vec3::UnitZ();
};

/// In a handover the partner stands at its transition configuration while this robot approaches (the
/// giver, holding the object) and while this robot retreats (giver first: the receiver holding the
/// object; then the receiver: the giver where its retreat ended, empty-handed). Before and after.
std::pair<std::optional<RobotState>, std::optional<RobotState>> partnersAround(const TaskArc& a,
                                                                               const TransitionConfig& tc,
                                                                               bool receiver, const GiverState& giver) {
  if (a.type != TaskArcType::kHandover) return {};
  if (receiver)
    return {RobotState{a.robot, tc.q, HeldObject{a.object, tc.X_TO}}, RobotState{a.robot, giver.q_post, HeldObject{}}};
  return {std::nullopt, RobotState{a.robot2, tc.q2, HeldObject{a.object, tc.X_TO2}}};
}

}  // namespace

struct MotionConstruction {
  MotionLayer& layer;
  const TaskPlan& plan;
  const std::vector<TransitionConfig>& transitions;
  const TaskSpace& space;
  const Scene& scene = space.scene();
  lazy::MotionHypergraph& graph = layer.graph_;
  MotionAnchors h;
  std::vector<int> last;  ///< per robot: its last visit so far, -1: none
  std::vector<std::optional<VertexId>> object_at;
  std::vector<VertexId> task_at;

  MotionAnchors run();
  /// The source: every robot home, every object at its start, every task pending.
  void addSource();
  /// One robot's part in step k (role 1: a handover's receiver): its anchors and H_M's elements for them.
  void addVisit(int k, int role, GiverState& giver);
  /// Step k's transition hyperarc, after its visits.
  void addTransition(int k);
  /// Every robot's way home (when the scene wants it) and the sink.
  void addHomes();
  /// The move robot r makes from its previous visit's retreat end (or home) to `to`.
  void addTransit(int r, int previous, VertexId to, const JointVector& q_to);
};

MotionAnchors MotionConstruction::run() {
  h.layouts = restingAlong(plan, space).layouts;
  last.assign(scene.robots.size(), -1);
  addSource();
  for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
    GiverState giver;
    giver.q_post = transitions[k].q;
    h.step_visits.emplace_back();
    for (int role = 0; role < (plan.steps[k].action.type == TaskArcType::kHandover ? 2 : 1); ++role)
      addVisit(k, role, giver);
    addTransition(k);
  }
  addHomes();
  return std::move(h);
}

void MotionConstruction::addSource() {
  std::vector<VertexId> start;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    h.home.push_back(graph.robotVertex(r, TaskElement::robotAlone(r), scene.robots[r].home));
    start.push_back(h.home.back());
  }
  object_at.resize(static_cast<std::size_t>(space.objectCount()));
  for (int o = 0; o < space.objectCount(); ++o) {
    const int l = space.startLocation(o);
    object_at[o] = graph.objectVertex(o, l, space.location(o, l).X_WO);
    start.push_back(*object_at[o]);
  }
  for (int t = 0; t < static_cast<int>(scene.tasks.size()); ++t) {
    task_at.push_back(graph.taskVertex(t, false));
    start.push_back(task_at.back());
  }
  h.source = graph.source(start);
}

void MotionConstruction::addTransit(int r, int previous, VertexId to, const JointVector& q_to) {
  const JointVector& from = previous < 0 ? scene.robots[r].home : h.visits[previous].post.front();
  const VertexId from_vertex = previous < 0 ? h.home[r] : h.visits[previous].post_vertex.front();
  graph.move(from_vertex, to, {from, q_to}, false);
}

void MotionConstruction::addVisit(int k, int role, GiverState& giver) {
  const TaskArc& a = plan.steps[k].action;
  const TransitionConfig& tc = transitions[k];
  const bool receiver = role == 1;
  VisitAnchors v;
  v.robot = receiver ? a.robot2 : a.robot;
  const int r = v.robot;
  const Roles held = heldAround(a, tc, receiver);
  v.visit.step = k;
  v.visit.receiver = receiver;
  v.visit.q = receiver ? tc.q2 : tc.q;
  v.visit.held_before = held.before;
  v.visit.held_after = held.after;
  v.is_giver = a.type == TaskArcType::kHandover && !receiver;
  const auto [partner_before, partner_after] = partnersAround(a, tc, receiver, giver);
  // The giver brings the object straight to the handover pose; everyone else approaches along the TCP
  // axis so that fingers slide around the object instead of sweeping through it.
  v.pre.push_back(v.is_giver ? v.visit.q
                             : layer.backedOff(r, v.visit.q, held.before, h.layouts[k], {}, 0.0, partner_before)
                                   .value_or(v.visit.q));
  // The giver cannot back off (its approach axis leads out of reach): the receiver pulls the object out
  // of the giver's open fingers along the giver's approach axis instead.
  v.own_axis = !(receiver && !giver.backs_off);
  const std::optional<Vec3> retreat_axis = v.own_axis ? std::optional<Vec3>() : giver.approach_W;
  v.post.push_back(layer.backedOff(r, v.visit.q, held.after, h.layouts[k + 1], retreat_axis, 0.0, partner_after)
                       .value_or(v.visit.q));
  if (v.is_giver) {
    giver.q_post = v.post.front();
    giver.backs_off = (v.post.front() - v.visit.q).cwiseAbs().maxCoeff() > 1e-12;
    const SceneRobot& sr = scene.robots[r];
    giver.approach_W = forwardKinematics(*sr.model, sr.X_WB, v.visit.q).X_WT.linear().col(2);
  }
  v.context = MotionContext{held.before, h.layouts[k], {},
                            layer.constraints_ ? layer.constraints_->regionsFor(plan, r, k, v.visit.q) : std::vector<Aabb>{}};
  const auto [e_before, e_after] = elementsAround(a, r);
  v.pre_vertex.push_back(graph.robotVertex(r, e_before, v.pre.front()));
  v.at_q = graph.robotVertex(r, e_before, v.visit.q);
  v.after_q = graph.robotVertex(r, e_after, v.visit.q);
  v.post_vertex.push_back(graph.robotVertex(r, e_after, v.post.front()));
  v.previous = last[r];
  addTransit(r, v.previous, v.pre_vertex.front(), v.pre.front());
  graph.move(v.pre_vertex.front(), v.at_q, {v.pre.front(), v.visit.q});
  graph.move(v.after_q, v.post_vertex.front(), {v.visit.q, v.post.front()});
  last[r] = static_cast<int>(h.visits.size());
  h.step_visits.back().push_back(last[r]);
  h.visits.push_back(std::move(v));
}

void MotionConstruction::addTransition(int k) {
  const TaskArc& a = plan.steps[k].action;
  std::vector<VertexId> tail, head;
  for (int i : h.step_visits[k]) {
    tail.push_back(h.visits[i].at_q);
    head.push_back(h.visits[i].after_q);
  }
  if (a.type == TaskArcType::kPick && object_at[a.object]) {
    tail.push_back(*object_at[a.object]);
    object_at[a.object].reset();
  }
  // An inspection takes its task from pending to done (so the hyperarc is no self-loop).
  if (a.type == TaskArcType::kInspect && a.task >= 0 && a.task < static_cast<int>(task_at.size())) {
    tail.push_back(task_at[a.task]);
    task_at[a.task] = graph.taskVertex(a.task, true);
    head.push_back(task_at[a.task]);
  }
  if (a.type == TaskArcType::kPlace) {
    object_at[a.object] = graph.objectVertex(a.object, a.location, space.location(a.object, a.location).X_WO);
    head.push_back(*object_at[a.object]);
  }
  h.transition.push_back(graph.transition(a, tail, head));
}

void MotionConstruction::addHomes() {
  for (const auto& o : object_at)
    if (o) h.end_items.push_back(*o);
  h.end_items.insert(h.end_items.end(), task_at.begin(), task_at.end());
  if (!scene.end_at_home) return;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    VisitAnchors v;
    v.robot = r;
    v.home = true;
    v.visit.step = static_cast<int>(plan.steps.size());
    v.visit.q = scene.robots[r].home;
    v.pre = {v.visit.q};
    v.pre_vertex = {h.home[r]};
    v.at_q = v.after_q = h.home[r];
    v.context = MotionContext{{}, h.layouts.back(), {}};
    v.previous = last[r];
    addTransit(r, v.previous, h.home[r], v.visit.q);
    h.visits.push_back(std::move(v));
  }
}

MotionAnchors MotionLayer::construct(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                     const TaskSpace& space) {
  log::PhaseTimer construction(*emitter_, log::Phase::MotionConstruction);
  return MotionConstruction{*this, plan, transitions, space}.run();
}

}  // namespace dash
