#include "engine/task/task_hypergraph.h"

#include <deque>
#include <unordered_set>

namespace dash {

const char* graspClassName(GraspClass g) {
  switch (g) {
    case GraspClass::kTop: return "top";
    case GraspClass::kSide: return "side";
    case GraspClass::kBottom: return "bottom";
  }
  return "?";
}

const char* taskArcTypeName(TaskArcType t) {
  switch (t) {
    case TaskArcType::kSource: return "source";
    case TaskArcType::kSink: return "sink";
    case TaskArcType::kPick: return "pick";
    case TaskArcType::kPlace: return "place";
    case TaskArcType::kHandover: return "handover";
    case TaskArcType::kInspect: return "inspect";
  }
  return "?";
}

bool handoverClassesCompatible(GraspClass giver, GraspClass receiver) {
  return giver == GraspClass::kSide || giver != receiver;
}

namespace {
constexpr GraspClass kClasses[kGraspClassCount] = {GraspClass::kTop, GraspClass::kSide, GraspClass::kBottom};

bool canManipulate(const SceneRobot& robot) { return robot.hasCapability("grasp"); }
}  // namespace

std::string elementLabel(const TaskElement& e, const TaskSpace& space) {
  const Scene& scene = space.scene();
  switch (e.kind) {
    case ElementKind::kRobot: return scene.robots[e.robot].id;
    case ElementKind::kHolding:
      return scene.robots[e.robot].id + "+" + scene.objects[e.object].id + "(" + graspClassName(e.grasp) + ")";
    case ElementKind::kObjectAt: return space.locationLabel(e.object, e.location);
    case ElementKind::kTaskPending: return "inspect#" + std::to_string(e.task) + " pending";
    case ElementKind::kTaskDone: return "inspect#" + std::to_string(e.task) + " done";
    case ElementKind::kSource: return "source";
    case ElementKind::kSink: return "sink";
  }
  return "?";
}

std::string TaskHypergraph::label(VertexId v, const TaskSpace& space) const {
  return elementLabel(graph_.property(v), space);
}

std::string TaskHypergraph::label(HyperarcId a, const TaskSpace& space) const {
  const TaskArc& arc = graph_.property(a);
  const Scene& scene = space.scene();
  std::string s = taskArcTypeName(arc.type);
  if (arc.robot >= 0) s += " " + scene.robots[arc.robot].id;
  if (arc.robot2 >= 0) s += "->" + scene.robots[arc.robot2].id;
  if (arc.object >= 0) s += " " + scene.objects[arc.object].id;
  if (arc.type == TaskArcType::kPick || arc.type == TaskArcType::kPlace)
    s += " " + space.locationLabel(arc.object, arc.location) + " (" + graspClassName(arc.grasp) + ")";
  if (arc.type == TaskArcType::kHandover)
    s += std::string(" (") + graspClassName(arc.grasp) + "->" + graspClassName(arc.grasp2) + ")";
  if (arc.type == TaskArcType::kInspect) s += " task#" + std::to_string(arc.task);
  return s;
}

VertexId TaskHypergraph::addVertex(const TaskElement& e, const Observer& observer) {
  const auto [id, inserted] = graph_.addVertex(e);
  if (inserted && observer.onVertex) observer.onVertex(id, e);
  return id;
}

void TaskHypergraph::addArc(std::vector<VertexId> tail, std::vector<VertexId> head, const TaskArc& arc,
                            const Observer& observer) {
  const auto [id, inserted] = graph_.addHyperarc(std::move(tail), std::move(head), arc);
  if (inserted && observer.onHyperarc) observer.onHyperarc(id, arc);
}

void TaskHypergraph::build(const TaskSpace& space, const TaskReachability& reach, const Observer& observer) {
  const Scene& scene = space.scene();
  const VertexId src = addVertex(TaskElement::source(), observer);
  const VertexId snk = addVertex(TaskElement::sink(), observer);

  std::vector<VertexId> start_head;
  std::vector<VertexId> goal_tail;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    const VertexId v = addVertex(TaskElement::robotAlone(r), observer);
    start_head.push_back(v);
    goal_tail.push_back(v);
  }
  for (int o = 0; o < space.objectCount(); ++o) {
    start_head.push_back(addVertex(TaskElement::objectAt(o, space.startLocation(o)), observer));
    const int goal = space.goalLocation(o);
    if (goal >= 0) goal_tail.push_back(addVertex(TaskElement::objectAt(o, goal), observer));
  }
  for (int k = 0; k < static_cast<int>(scene.tasks.size()); ++k) {
    start_head.push_back(addVertex(TaskElement::taskState(k, false), observer));
    goal_tail.push_back(addVertex(TaskElement::taskState(k, true), observer));
  }
  TaskArc source_arc;
  source_arc.type = TaskArcType::kSource;
  TaskArc sink_arc;
  sink_arc.type = TaskArcType::kSink;
  // Add the source and sink first so that a fresh graph gives them the lowest hyperarc ids.
  {
    const auto [id, inserted] = graph_.addHyperarc({src}, start_head, source_arc);
    if (inserted && observer.onHyperarc) observer.onHyperarc(id, source_arc);
    source_ = id;
  }
  {
    const auto [id, inserted] = graph_.addHyperarc(goal_tail, {snk}, sink_arc);
    if (inserted && observer.onHyperarc) observer.onHyperarc(id, sink_arc);
    sink_ = id;
  }
  for (int o = 0; o < space.objectCount(); ++o)
    if (!space.isFixed(o)) closeObject(space, reach, o, observer);
  addInspections(space, reach, observer);
}

// Breadth-first closure over one object's states (at a location, or held by a robot with a grasp
// class): robots alone are always available, so the hypergraph's closure is the union of these.
void TaskHypergraph::closeObject(const TaskSpace& space, const TaskReachability& reach, int o,
                                 const Observer& observer) {
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  const auto& locations = space.locations(o);
  std::deque<TaskElement> queue;
  std::unordered_set<TaskElement> seen;
  auto push = [&](const TaskElement& e) {
    if (seen.insert(e).second) queue.push_back(e);
  };
  push(TaskElement::objectAt(o, space.startLocation(o)));
  while (!queue.empty()) {
    const TaskElement e = queue.front();
    queue.pop_front();
    const VertexId ve = addVertex(e, observer);
    if (e.kind == ElementKind::kObjectAt) {
      const Pose& X_WO = locations[e.location].X_WO;
      for (int r = 0; r < robots; ++r) {
        if (!canManipulate(scene.robots[r])) continue;
        for (GraspClass g : kClasses) {
          if (!reach.canGrasp(r, o, X_WO, g)) continue;
          const TaskElement held = TaskElement::holding(r, o, g);
          const VertexId vr = addVertex(TaskElement::robotAlone(r), observer);
          const VertexId vh = addVertex(held, observer);
          TaskArc pick{TaskArcType::kPick, static_cast<std::int16_t>(r), -1, static_cast<std::int16_t>(o),
                       e.location, -1, g, g, reach.graspCost(r, X_WO)};
          addArc({vr, ve}, {vh}, pick, observer);
          push(held);
        }
      }
    } else {  // held by e.robot with class e.grasp
      const int r = e.robot;
      const VertexId vr = addVertex(TaskElement::robotAlone(r), observer);
      for (int l = 0; l < static_cast<int>(locations.size()); ++l) {
        if (!reach.canGrasp(r, o, locations[l].X_WO, e.grasp)) continue;
        const TaskElement at = TaskElement::objectAt(o, l);
        const VertexId va = addVertex(at, observer);
        TaskArc place{TaskArcType::kPlace, static_cast<std::int16_t>(r), -1, static_cast<std::int16_t>(o),
                      static_cast<std::int16_t>(l), -1, e.grasp, e.grasp, reach.graspCost(r, locations[l].X_WO)};
        addArc({ve}, {vr, va}, place, observer);
        push(at);
      }
      for (int r2 = 0; r2 < robots; ++r2) {
        if (r2 == r || !canManipulate(scene.robots[r2])) continue;
        for (GraspClass g2 : kClasses) {
          if (!handoverClassesCompatible(e.grasp, g2) || !reach.canHandover(r, r2, o, e.grasp, g2)) continue;
          const TaskElement received = TaskElement::holding(r2, o, g2);
          const VertexId vr2 = addVertex(TaskElement::robotAlone(r2), observer);
          const VertexId vh2 = addVertex(received, observer);
          TaskArc handover{TaskArcType::kHandover, static_cast<std::int16_t>(r), static_cast<std::int16_t>(r2),
                           static_cast<std::int16_t>(o), -1, -1, e.grasp, g2, reach.handoverCost(r, r2)};
          addArc({ve, vr2}, {vr, vh2}, handover, observer);
          push(received);
        }
      }
    }
  }
}

// An inspection needs an inspect-capable robot and the covering object (the lid) away from its
// start: one hyperarc per robot and per non-start location of the lid. The lid element passes
// through the hyperarc unchanged (consumed and produced again), which keeps it on the frontier.
void TaskHypergraph::addInspections(const TaskSpace& space, const TaskReachability& reach,
                                    const Observer& observer) {
  const Scene& scene = space.scene();
  for (int k = 0; k < static_cast<int>(scene.tasks.size()); ++k) {
    const SceneTask& task = scene.tasks[k];
    const VertexId pending = addVertex(TaskElement::taskState(k, false), observer);
    const VertexId done = addVertex(TaskElement::taskState(k, true), observer);
    for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
      if (!scene.robots[r].hasCapability(task.capability) || !reach.canInspect(r, k)) continue;
      const VertexId vr = addVertex(TaskElement::robotAlone(r), observer);
      TaskArc inspect{TaskArcType::kInspect, static_cast<std::int16_t>(r), -1,
                      static_cast<std::int16_t>(task.requires_removed_object), -1,
                      static_cast<std::int16_t>(k), GraspClass::kTop, GraspClass::kTop,
                      reach.graspCost(r, task.X_WT)};
      const int lid = task.requires_removed_object;
      if (lid < 0) {
        addArc({vr, pending}, {vr, done}, inspect, observer);
        continue;
      }
      for (int l = 0; l < static_cast<int>(space.locations(lid).size()); ++l) {
        if (l == space.startLocation(lid)) continue;
        const auto at = graph_.find(TaskElement::objectAt(lid, l));
        if (!at) continue;  // the lid cannot get there
        inspect.location = static_cast<std::int16_t>(l);
        addArc({vr, pending, *at}, {vr, done, *at}, inspect, observer);
      }
    }
  }
}

}  // namespace dash
