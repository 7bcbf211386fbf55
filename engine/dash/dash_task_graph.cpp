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

namespace {

using Holds = std::vector<std::array<bool, kGraspClassCount>>;  ///< per robot, per class: can hold it so

// One construction of H_T, its steps as methods: source and sink, then per object its picks and
// places and the handovers they open, then the inspections. The order is the order of the ids.
class DashTaskGraphBuilder {
 public:
  DashTaskGraphBuilder(const TaskSpace& space, const TaskReachability& reach, const DashTaskGraphObserver& observer)
      : space_(space), reach_(reach), observer_(observer), scene_(space.scene()),
        robots_(static_cast<int>(scene_.robots.size())) {}

  DashTaskGraph build() {
    addSourceAndSink();
    for (int o = 0; o < space_.objectCount(); ++o) {
      if (space_.isFixed(o)) continue;
      addHandovers(o, addPicksAndPlaces(o));
    }
    for (int k = 0; k < static_cast<int>(scene_.tasks.size()); ++k) addInspects(k);
    return std::move(g_);
  }

 private:
  VertexId vertex(const TaskElement& e) {
    const auto [id, inserted] = g_.addVertex(e);
    if (inserted && observer_.onVertex) observer_.onVertex(id, e);
    return id;
  }

  void arc(std::vector<VertexId> tail, std::vector<VertexId> head, const TaskArc& a) {
    const auto [id, inserted] = g_.addHyperarc(std::move(tail), std::move(head), a);
    if (inserted && observer_.onHyperarc) observer_.onHyperarc(id, a, g_.tail(id), g_.head(id));
  }

  void addSourceAndSink() {
    const VertexId src = vertex(TaskElement::source());
    const VertexId snk = vertex(TaskElement::sink());
    std::vector<VertexId> start_head, goal_tail;
    for (int r = 0; r < robots_; ++r) {
      start_head.push_back(vertex(TaskElement::robotAlone(r)));
      goal_tail.push_back(start_head.back());
    }
    for (int o = 0; o < space_.objectCount(); ++o) {
      const VertexId v = vertex(TaskElement::objectAt(o, -1));
      start_head.push_back(v);
      if (space_.goalLocation(o) >= 0) goal_tail.push_back(v);
    }
    for (int k = 0; k < static_cast<int>(scene_.tasks.size()); ++k) {
      start_head.push_back(vertex(TaskElement::taskState(k, false)));
      goal_tail.push_back(vertex(TaskElement::taskState(k, true)));
    }
    arc({src}, start_head, TaskArc{.type = TaskArcType::kSource});
    arc(goal_tail, {snk}, TaskArc{.type = TaskArcType::kSink});
  }

  // Picks and places at any placement; which robots can then hold the object with which class.
  Holds addPicksAndPlaces(int o) {
    const VertexId vo = *g_.find(TaskElement::objectAt(o, -1));
    Holds holds(static_cast<std::size_t>(robots_));
    for (int r = 0; r < robots_; ++r) {
      holds[r].fill(false);
      if (!canManipulate(scene_.robots[r])) continue;
      for (GraspClass c : kClasses) {
        double cost = -1.0;
        for (const ObjectLocation& l : space_.locations(o))
          if (reach_.canGrasp(r, o, l.X_WO, c)) {
            const double d = reach_.graspCost(r, l.X_WO);
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
    return holds;
  }

  // Handovers: every arm pair in range and compatible classes. A robot may hold the object with a
  // class it cannot pick with (it receives it), so the classes close over handovers.
  void addHandovers(int o, Holds holds) {
    bool grew = true;
    while (grew) {
      grew = false;
      for (int r = 0; r < robots_; ++r)
        for (GraspClass c1 : kClasses) {
          if (!holds[r][static_cast<int>(c1)]) continue;
          for (int r2 = 0; r2 < robots_; ++r2) {
            if (r2 == r || !canManipulate(scene_.robots[r2])) continue;
            for (GraspClass c2 : kClasses) grew = addHandover(o, r, c1, r2, c2, holds) || grew;
          }
        }
    }
  }

  // The handover of o from r (class c1) to r2 (class c2) if possible; whether r2 may now hold it with
  // a class it could not before.
  bool addHandover(int o, int r, GraspClass c1, int r2, GraspClass c2, Holds& holds) {
    if (!handoverClassesCompatible(c1, c2) || !reach_.canHandover(r, r2, o, c1, c2)) return false;
    const VertexId vh = vertex(TaskElement::holding(r, o, c1));
    const VertexId vr2 = vertex(TaskElement::robotAlone(r2));
    const VertexId vr = vertex(TaskElement::robotAlone(r));
    const VertexId vh2 = vertex(TaskElement::holding(r2, o, c2));
    arc({vh, vr2}, {vr, vh2},
        TaskArc{TaskArcType::kHandover, i16(r), i16(r2), i16(o), -1, -1, c1, c2, reach_.handoverCost(r, r2)});
    if (holds[r2][static_cast<int>(c2)]) return false;
    holds[r2][static_cast<int>(c2)] = true;
    return true;
  }

  void addInspects(int k) {
    const SceneTask& task = scene_.tasks[k];
    const VertexId pending = vertex(TaskElement::taskState(k, false));
    const VertexId done = vertex(TaskElement::taskState(k, true));
    for (int r = 0; r < robots_; ++r) {
      if (!scene_.robots[r].hasCapability(task.capability) || !reach_.canInspect(r, k)) continue;
      const VertexId vr = vertex(TaskElement::robotAlone(r));
      TaskArc inspect{TaskArcType::kInspect, i16(r), -1, i16(task.requires_removed_object), -1, i16(k),
                      GraspClass::kTop, GraspClass::kTop, reach_.graspCost(r, task.X_WT)};
      if (task.requires_removed_object < 0) {
        arc({vr, pending}, {vr, done}, inspect);
      } else {
        // The lid passes through unchanged; where it must be (away from its start) is a motion-level
        // matter: the motion hypergraph has one inspect hyperarc per lid placement.
        const VertexId lid = *g_.find(TaskElement::objectAt(task.requires_removed_object, -1));
        arc({vr, pending, lid}, {vr, done, lid}, inspect);
      }
    }
  }

  const TaskSpace& space_;
  const TaskReachability& reach_;
  const DashTaskGraphObserver& observer_;
  const Scene& scene_;
  const int robots_;
  DashTaskGraph g_;
};

}  // namespace

DashTaskGraph buildDashTaskGraph(const TaskSpace& space, const TaskReachability& reach,
                                 const DashTaskGraphObserver& observer) {
  return DashTaskGraphBuilder(space, reach, observer).build();
}

}  // namespace dash
