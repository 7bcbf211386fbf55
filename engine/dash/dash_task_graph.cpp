#include "engine/dash/dash_task_graph.h"

#include <array>

namespace dash {

namespace {
constexpr GraspClass kClasses[kGraspClassCount] = {GraspClass::kTop, GraspClass::kSide, GraspClass::kBottom};

bool canManipulate(const SceneRobot& robot) { return robot.hasCapability("grasp"); }

std::int16_t i16(int v) { return static_cast<std::int16_t>(v); }
}  // namespace

std::string dashElementLabel(const TaskElement& e, const Scene& scene) {
  switch (e.kind) {
    case ElementKind::kRobot: return scene.robots[e.robot].id;
    case ElementKind::kHolding:
      return scene.robots[e.robot].id + "+" + scene.objects[e.object].id + "(" + graspClassName(e.grasp) + ")";
    case ElementKind::kObjectAt: return scene.objects[e.object].id;
    case ElementKind::kTaskPending: return "inspect#" + std::to_string(e.task) + " pending";
    case ElementKind::kTaskDone: return "inspect#" + std::to_string(e.task) + " done";
    case ElementKind::kSource: return "source";
    case ElementKind::kSink: return "sink";
  }
  return "?";
}

DashTaskGraph buildDashTaskGraph(const TaskSpace& space, const TaskReachability& reach,
                                 const DashTaskGraphObserver& observer) {
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  DashTaskGraph g;
  auto vertex = [&](const TaskElement& e) {
    const auto [id, inserted] = g.addVertex(e);
    if (inserted && observer.onVertex) observer.onVertex(id, e);
    return id;
  };
  auto arc = [&](std::vector<VertexId> tail, std::vector<VertexId> head, const TaskArc& a) {
    const auto [id, inserted] = g.addHyperarc(std::move(tail), std::move(head), a);
    if (inserted && observer.onHyperarc) observer.onHyperarc(id, a, g.tail(id), g.head(id));
  };

  const VertexId src = vertex(TaskElement::source());
  const VertexId snk = vertex(TaskElement::sink());
  std::vector<VertexId> start_head, goal_tail;
  for (int r = 0; r < robots; ++r) {
    start_head.push_back(vertex(TaskElement::robotAlone(r)));
    goal_tail.push_back(start_head.back());
  }
  for (int o = 0; o < space.objectCount(); ++o) {
    const VertexId v = vertex(TaskElement::objectAt(o, -1));
    start_head.push_back(v);
    if (space.goalLocation(o) >= 0) goal_tail.push_back(v);
  }
  for (int k = 0; k < static_cast<int>(scene.tasks.size()); ++k) {
    start_head.push_back(vertex(TaskElement::taskState(k, false)));
    goal_tail.push_back(vertex(TaskElement::taskState(k, true)));
  }
  arc({src}, start_head, TaskArc{.type = TaskArcType::kSource});
  arc(goal_tail, {snk}, TaskArc{.type = TaskArcType::kSink});

  for (int o = 0; o < space.objectCount(); ++o) {
    if (space.isFixed(o)) continue;
    const VertexId vo = *g.find(TaskElement::objectAt(o, -1));
    // Which robots can hold the object with which class: picks at any placement.
    std::vector<std::array<bool, kGraspClassCount>> holds(static_cast<std::size_t>(robots));
    for (int r = 0; r < robots; ++r) {
      holds[r].fill(false);
      if (!canManipulate(scene.robots[r])) continue;
      for (GraspClass c : kClasses) {
        double cost = -1.0;
        for (const ObjectLocation& l : space.locations(o))
          if (reach.canGrasp(r, o, l.X_WO, c)) {
            const double d = reach.graspCost(r, l.X_WO);
            cost = cost < 0.0 ? d : std::min(cost, d);
          }
        if (cost < 0.0) continue;
        holds[r][static_cast<int>(c)] = true;
        const VertexId vr = vertex(TaskElement::robotAlone(r));
        const VertexId vh = vertex(TaskElement::holding(r, o, c));
        TaskArc pick{TaskArcType::kPick, i16(r), -1, i16(o), -1, -1, c, c, cost};
        arc({vr, vo}, {vh}, pick);
        TaskArc place = pick;
        place.type = TaskArcType::kPlace;
        arc({vh}, {vr, vo}, place);
      }
    }
    // Handovers: every arm pair in range and compatible classes. A robot may hold the object with a
    // class it cannot pick with (it receives it), so the classes close over handovers.
    bool grew = true;
    while (grew) {
      grew = false;
      for (int r = 0; r < robots; ++r)
        for (GraspClass c1 : kClasses) {
          if (!holds[r][static_cast<int>(c1)]) continue;
          for (int r2 = 0; r2 < robots; ++r2) {
            if (r2 == r || !canManipulate(scene.robots[r2])) continue;
            for (GraspClass c2 : kClasses) {
              if (!handoverClassesCompatible(c1, c2) || !reach.canHandover(r, r2, o, c1, c2)) continue;
              const VertexId vh = vertex(TaskElement::holding(r, o, c1));
              const VertexId vr2 = vertex(TaskElement::robotAlone(r2));
              const VertexId vr = vertex(TaskElement::robotAlone(r));
              const VertexId vh2 = vertex(TaskElement::holding(r2, o, c2));
              arc({vh, vr2}, {vr, vh2},
                  TaskArc{TaskArcType::kHandover, i16(r), i16(r2), i16(o), -1, -1, c1, c2, reach.handoverCost(r, r2)});
              if (!holds[r2][static_cast<int>(c2)]) grew = holds[r2][static_cast<int>(c2)] = true;
            }
          }
        }
    }
  }
  for (int k = 0; k < static_cast<int>(scene.tasks.size()); ++k) {
    const SceneTask& task = scene.tasks[k];
    const VertexId pending = vertex(TaskElement::taskState(k, false));
    const VertexId done = vertex(TaskElement::taskState(k, true));
    for (int r = 0; r < robots; ++r) {
      if (!scene.robots[r].hasCapability(task.capability) || !reach.canInspect(r, k)) continue;
      const VertexId vr = vertex(TaskElement::robotAlone(r));
      TaskArc inspect{TaskArcType::kInspect, i16(r), -1, i16(task.requires_removed_object), -1, i16(k),
                      GraspClass::kTop, GraspClass::kTop, reach.graspCost(r, task.X_WT)};
      if (task.requires_removed_object < 0) {
        arc({vr, pending}, {vr, done}, inspect);
      } else {
        // The lid passes through unchanged; where it must be (away from its start) is a motion-level
        // matter: the motion hypergraph has one inspect hyperarc per lid placement.
        const VertexId lid = *g.find(TaskElement::objectAt(task.requires_removed_object, -1));
        arc({vr, pending, lid}, {vr, done, lid}, inspect);
      }
    }
  }
  return g;
}

}  // namespace dash
