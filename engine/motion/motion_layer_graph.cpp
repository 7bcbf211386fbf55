// MotionLayer's part that keeps H_M: the traced schedule's motions added to the persistent motion
// hypergraph (deduplicated), then the motion query over it along the schedule (H_ME).
#include "engine/motion/motion_layer.h"

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

}  // namespace

void MotionLayer::recordInHypergraph(const TaskPlan& plan, const std::vector<TransitionConfig>&,
                                     const TaskSpace& space, const MotionLayerResult& result,
                                     const Deadline& deadline) {
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  std::vector<HyperarcId> sequence;
  std::optional<HyperarcId> sink;
  HyperarcId source;
  {
    // Anchors and hyperarcs of this schedule: construction of H_M (only what it lacks is added).
    log::PhaseTimer construction(*emitter_, log::Phase::MotionConstruction);
    std::vector<VertexId> robot_at(static_cast<std::size_t>(robots));
    std::vector<std::optional<VertexId>> object_at(static_cast<std::size_t>(space.objectCount()));
    std::vector<VertexId> start;
    for (int r = 0; r < robots; ++r) {
      robot_at[r] = graph_.robotVertex(r, TaskElement::robotAlone(r), scene.robots[r].home);
      start.push_back(robot_at[r]);
    }
    for (int o = 0; o < space.objectCount(); ++o) {
      const int l = space.startLocation(o);
      object_at[o] = graph_.objectVertex(o, l, space.location(o, l).X_WO);
      start.push_back(*object_at[o]);
    }
    std::vector<VertexId> task_at;
    for (int t = 0; t < static_cast<int>(scene.tasks.size()); ++t) {
      task_at.push_back(graph_.taskVertex(t, false));
      start.push_back(task_at.back());
    }
    source = graph_.source(start);
    auto add = [&](std::optional<HyperarcId> arc) {
      if (arc) sequence.push_back(*arc);
    };
    std::vector<std::size_t> next(static_cast<std::size_t>(robots), 0);
    bool complete = result.status == MotionStatus::kOk;
    for (int k = 0; k < static_cast<int>(plan.steps.size()); ++k) {
      const TaskArc& a = plan.steps[k].action;
      std::vector<int> parts{a.robot};
      if (a.type == TaskArcType::kHandover) parts.push_back(a.robot2);
      bool traced = true;
      for (int r : parts) {
        const auto& visits = result.robots[r].visits;
        traced = traced && next[r] < visits.size() && visits[next[r]].step == k;
      }
      if (!traced) {
        complete = false;
        break;
      }
      // Each participant gets to its transition configuration: transit, then approach.
      std::vector<VertexId> before, after;
      for (int r : parts) {
        const StepVisit& v = result.robots[r].visits[next[r]];
        const auto [e_before, e_after] = elementsAround(a, r);
        const VertexId pre = graph_.robotVertex(r, e_before, v.q_pre);
        add(graph_.move(robot_at[r], pre, v.transit));
        const VertexId at_q = graph_.robotVertex(r, e_before, v.q);
        add(graph_.move(pre, at_q, {v.q_pre, v.q}));
        before.push_back(at_q);
        after.push_back(graph_.robotVertex(r, e_after, v.q));
      }
      // The transition: one hyperarc, coupling both robots in a handover.
      std::vector<VertexId> tail = before, head = after;
      if (a.type == TaskArcType::kPick && object_at[a.object]) {
        tail.push_back(*object_at[a.object]);
        object_at[a.object].reset();
      }
      // An inspection takes its task from pending to done (so the hyperarc is no self-loop).
      if (a.type == TaskArcType::kInspect && a.task >= 0 && a.task < static_cast<int>(task_at.size())) {
        tail.push_back(task_at[a.task]);
        task_at[a.task] = graph_.taskVertex(a.task, true);
        head.push_back(task_at[a.task]);
      }
      if (a.type == TaskArcType::kPlace) {
        object_at[a.object] = graph_.objectVertex(a.object, a.location, space.location(a.object, a.location).X_WO);
        head.push_back(*object_at[a.object]);
      }
      sequence.push_back(graph_.transition(a, tail, head));
      // Retreats.
      for (std::size_t i = 0; i < parts.size(); ++i) {
        const int r = parts[i];
        const StepVisit& v = result.robots[r].visits[next[r]++];
        const VertexId post = graph_.robotVertex(r, elementsAround(a, r).second, v.q_post);
        add(graph_.move(after[i], post, {v.q, v.q_post}));
        robot_at[r] = post;
      }
    }
    if (complete) {
      std::vector<VertexId> end;
      for (int r = 0; r < robots; ++r) {
        if (scene.end_at_home && !result.robots[r].home_path.empty()) {
          const VertexId home = graph_.robotVertex(r, TaskElement::robotAlone(r), scene.robots[r].home);
          add(graph_.move(robot_at[r], home, result.robots[r].home_path));
          robot_at[r] = home;
        }
        end.push_back(robot_at[r]);
      }
      for (const auto& o : object_at)
        if (o) end.push_back(*o);
      end.insert(end.end(), task_at.begin(), task_at.end());
      sink = graph_.sink(end);
    }
  }
  log::PhaseTimer query(*emitter_, log::Phase::MotionQuery);
  const lazy::MotionQueryCounts counts = graph_.query(source, sequence, sink, deadline);
  if (sink && !counts.reached_sink && !deadline.expired())
    emitter_->counter("motion_query_incomplete", 1);  // would be a bug: the schedule is a hyperpath of H_M
}

}  // namespace dash
