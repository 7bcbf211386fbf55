#include "engine/dash/motion_hypergraph.h"

#include <algorithm>
#include <cmath>

#include "engine/robots/cartesian_path.h"

namespace dash {

namespace {
std::vector<double> keyOf(const JointVector& q) { return std::vector<double>(q.data(), q.data() + q.size()); }
std::int16_t i16(int v) { return static_cast<std::int16_t>(v); }
bool sameHeld(const HeldObject& a, const HeldObject& b) {
  return a.object == b.object && (!a.holding() || a.X_TO.matrix() == b.X_TO.matrix());
}
}  // namespace

const char* motionArcTypeName(MotionArc::Type t) {
  switch (t) {
    case MotionArc::Type::kSource: return "source";
    case MotionArc::Type::kSink: return "sink";
    case MotionArc::Type::kMove: return "move";
    case MotionArc::Type::kPick: return "pick";
    case MotionArc::Type::kPlace: return "place";
    case MotionArc::Type::kHandover: return "handover";
    case MotionArc::Type::kInspect: return "inspect";
  }
  return "?";
}

VertexId MotionHypergraph::vertex(const MotionVertex& v) {
  const auto [id, inserted] = graph_.addVertex(v);
  if (inserted) {
    transitions_from_.emplace_back();
    spot_of_.push_back(-1);
    if (emitter_->enabled()) emitter_->vertex(log::Layer::Motion, id.value(), label(id));
  }
  return id;
}

HyperarcId MotionHypergraph::arc(std::vector<VertexId> tail, std::vector<VertexId> head, const MotionArc& a,
                                 double cost) {
  const auto [id, inserted] = graph_.addHyperarc(std::move(tail), std::move(head), a);
  if (inserted) {
    cost_.push_back(cost);
    emitter_->hyperarcOf(log::Layer::Motion, motionArcTypeName(a.type), id.value(), graph_.head(id), graph_.tail(id));
  }
  return id;
}

int MotionHypergraph::configIndex(int robot, const JointVector& q) {
  auto key = std::make_pair(robot, keyOf(q));
  if (auto it = config_index_.find(key); it != config_index_.end()) return it->second;
  configs_.push_back(q);
  config_index_.emplace(std::move(key), static_cast<int>(configs_.size()) - 1);
  return static_cast<int>(configs_.size()) - 1;
}

int MotionHypergraph::graspIndex(const Pose& X_TO) {
  for (std::size_t i = 0; i < grasps_.size(); ++i)
    if (grasps_[i].matrix() == X_TO.matrix()) return static_cast<int>(i);
  grasps_.push_back(X_TO);
  return static_cast<int>(grasps_.size()) - 1;
}

VertexId MotionHypergraph::robotVertex(int robot, const JointVector& q) {
  MotionVertex v;
  v.kind = MotionVertex::Kind::kRobot;
  v.robot = i16(robot);
  v.config = configIndex(robot, q);
  return vertex(v);
}

VertexId MotionHypergraph::holdingVertex(int robot, const HeldObject& held, const JointVector& q) {
  MotionVertex v;
  v.kind = MotionVertex::Kind::kHolding;
  v.robot = i16(robot);
  v.object = i16(held.object);
  v.grasp = graspIndex(held.X_TO);
  v.config = configIndex(robot, q);
  return vertex(v);
}

MotionHypergraph::Space& MotionHypergraph::space(int robot, const HeldObject& held) {
  for (Space& s : spaces_)
    if (s.robot == robot && sameHeld(s.held, held)) return s;
  spaces_.push_back({robot, held, {}, {}});
  return spaces_.back();
}

VertexId MotionHypergraph::restingVertex(int object, int placement) {
  MotionVertex v;
  v.kind = MotionVertex::Kind::kObject;
  v.object = i16(object);
  v.placement = i16(placement);
  return vertex(v);
}

VertexId MotionHypergraph::taskVertex(int task, bool done) {
  MotionVertex v;
  v.kind = done ? MotionVertex::Kind::kTaskDone : MotionVertex::Kind::kTaskPending;
  v.task = i16(task);
  return vertex(v);
}

// The order of these steps is the order of the vertex and hyperarc ids, which break the queries' ties.
MotionHypergraph::MotionHypergraph(const TaskSpace& space_in, const TransitionCatalog& catalog,
                                   log::EventEmitter& emitter)
    : space_(&space_in), catalog_(&catalog), emitter_(&emitter) {
  addSourceAndSink();
  addGraspArcs();
  addHandoverArcs();
  addInspectArcs();
}

void MotionHypergraph::addSourceAndSink() {
  const Scene& scene = space_->scene();
  const VertexId src = vertex(MotionVertex{.kind = MotionVertex::Kind::kSource});
  const VertexId snk = vertex(MotionVertex{.kind = MotionVertex::Kind::kSink});
  std::vector<VertexId> start, goal;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    home_.push_back(robotVertex(r, scene.robots[r].home));
    start.push_back(home_.back());
    goal.push_back(home_.back());
    Space& s = space(r, {});
    s.entries.push_back(home_.back());
    s.exits.push_back(home_.back());
  }
  addObjectVertices(start, goal);
  for (int k = 0; k < static_cast<int>(scene.tasks.size()); ++k) {
    start.push_back(taskVertex(k, false));
    goal.push_back(taskVertex(k, true));
  }
  source_ = arc({src}, start, MotionArc{MotionArc::Type::kSource}, 0.0);
  sink_ = arc(goal, {snk}, MotionArc{MotionArc::Type::kSink}, 0.0);
}

void MotionHypergraph::addObjectVertices(std::vector<VertexId>& start, std::vector<VertexId>& goal) {
  std::vector<Vec3> spots;  // extra locations at one position are one shared placement
  for (int o = 0; o < space_->objectCount(); ++o) {
    for (int p = 0; p < static_cast<int>(space_->locations(o).size()); ++p) {
      const VertexId v = restingVertex(o, p);
      const ObjectLocation& l = space_->location(o, p);
      if (l.kind != ObjectLocation::Kind::kExtra) continue;
      auto same = std::find_if(spots.begin(), spots.end(),
                               [&](const Vec3& q) { return (q - l.X_WO.translation()).norm() < 1e-9; });
      const int spot = static_cast<int>(same - spots.begin());
      if (same == spots.end()) {
        spots.push_back(l.X_WO.translation());
        spot_vertices_.emplace_back();
      }
      spot_of_[v.value()] = spot;
      spot_vertices_[spot].push_back(v);
    }
    start.push_back(restingVertex(o, space_->startLocation(o)));
    if (space_->goalLocation(o) >= 0) goal.push_back(restingVertex(o, space_->goalLocation(o)));
  }
}

void MotionHypergraph::addGraspArcs() {
  for (std::size_t i = 0; i < catalog_->grasps.size(); ++i) {
    const GraspSample& g = catalog_->grasps[i];
    const VertexId pre = robotVertex(g.robot, g.q_pre);
    const VertexId hold = holdingVertex(g.robot, g.held, g.q_hold);
    const VertexId at = restingVertex(g.object, g.placement);
    const double cost = pathLength(g.pre_path) + pathLength(g.hold_path);
    const int index = static_cast<int>(i);
    transitions_from_[pre.value()].push_back(arc({pre, at}, {hold}, {MotionArc::Type::kPick, index}, cost));
    transitions_from_[hold.value()].push_back(arc({hold}, {pre, at}, {MotionArc::Type::kPlace, index}, cost));
    Space& empty = space(g.robot, {});
    empty.entries.push_back(pre);
    empty.exits.push_back(pre);
    Space& holding = space(g.robot, g.held);
    holding.entries.push_back(hold);
    holding.exits.push_back(hold);
  }
}

void MotionHypergraph::addHandoverArcs() {
  for (std::size_t i = 0; i < catalog_->handovers.size(); ++i) {
    const HandoverSample& h = catalog_->handovers[i];
    const VertexId v1 = holdingVertex(h.giver, h.held, h.q1);
    const VertexId v1post = robotVertex(h.giver, h.q1_post);
    const VertexId v2pre = robotVertex(h.receiver, h.q2_pre);
    const VertexId v2post = holdingVertex(h.receiver, h.held2, h.q2_post);
    const double cost = pathLength(h.q1_post_path) + pathLength(h.q2_pre_path) + pathLength(h.q2_post_path);
    const HyperarcId a = arc({v1, v2pre}, {v1post, v2post}, {MotionArc::Type::kHandover, static_cast<int>(i)}, cost);
    transitions_from_[v1.value()].push_back(a);
    transitions_from_[v2pre.value()].push_back(a);
    space(h.giver, h.held).exits.push_back(v1);
    space(h.giver, {}).entries.push_back(v1post);
    space(h.receiver, {}).exits.push_back(v2pre);
    space(h.receiver, h.held2).entries.push_back(v2post);
  }
}

void MotionHypergraph::addInspectArcs() {
  for (std::size_t i = 0; i < catalog_->inspects.size(); ++i) {
    const InspectSample& s = catalog_->inspects[i];
    const VertexId pre = robotVertex(s.robot, s.q_pre);
    const VertexId pending = taskVertex(s.task, false);
    const VertexId done = taskVertex(s.task, true);
    const double cost = 2.0 * pathLength(s.pre_path);
    const int lid = space_->scene().tasks[s.task].requires_removed_object;
    const int index = static_cast<int>(i);
    if (lid < 0) {
      transitions_from_[pre.value()].push_back(arc({pre, pending}, {pre, done}, {MotionArc::Type::kInspect, index}, cost));
    } else {
      for (int p = 0; p < static_cast<int>(space_->locations(lid).size()); ++p) {
        if (p == space_->startLocation(lid)) continue;
        const VertexId at = restingVertex(lid, p);
        transitions_from_[pre.value()].push_back(
            arc({pre, pending, at}, {pre, done, at}, {MotionArc::Type::kInspect, index, p}, cost));
      }
    }
    Space& empty = space(s.robot, {});
    empty.entries.push_back(pre);
    empty.exits.push_back(pre);
  }
}

void MotionHypergraph::connectMoves(RoadmapSet& roadmaps, const std::vector<int>& robots, const Deadline& deadline) {
  // A move e -> x of cost `length` along path() (made only when needed), or a shorter path for one
  // already there.
  auto addMove = [&](int robot, const HeldObject& held, VertexId e, VertexId x, double length, auto path, bool back) {
    const auto key = std::make_pair(e.value(), x.value());
    if (auto it = move_of_.find(key); it != move_of_.end()) {
      MovePath& m = moves_[it->second];
      if (length < m.length - 1e-12) {  // a shorter path through new milestones
        m.path = path();
        m.length = length;
        cost_[graph_.find({e}, {x}, MotionArc{MotionArc::Type::kMove, it->second})->value()] = length;
      }
      return;
    }
    const int index = static_cast<int>(moves_.size());
    moves_.push_back({robot, held, e, x, path(), length, back});
    move_of_.emplace(key, index);
    arc({e}, {x}, MotionArc{MotionArc::Type::kMove, index}, length);
  };
  // A robot waiting where a handover needs it (an exit no transition leaves it at) may leave if the
  // handover does not happen: empty-handed back home, holding back to where it took the object; from
  // there every exit is a move away again. Those moves come after every other (hyperarc ids break the
  // queries' ties, so the greedy pass, which leaves them out, sees the same H_M as without them).
  std::vector<MovePath> backs;
  for (Space& sp : spaces_) {
    if (!robots.empty() && std::find(robots.begin(), robots.end(), sp.robot) == robots.end()) continue;
    if (deadline.expired()) return;
    ValidatedRoadmap& roadmap = roadmaps.at(sp.robot, sp.held.holding());
    const int s = roadmap.space(sp.held);
    for (auto* list : {&sp.entries, &sp.exits}) {
      std::sort(list->begin(), list->end());
      list->erase(std::unique(list->begin(), list->end()), list->end());
    }
    std::map<VertexId, int> at;
    for (const auto* list : {&sp.entries, &sp.exits})
      for (VertexId v : *list)
        if (!at.contains(v)) at[v] = roadmap.anchor(s, configs_[graph_.property(v).config]);
    for (VertexId e : sp.entries) {
      if (deadline.expired()) return;
      const ValidatedRoadmap::Tree tree = roadmap.shortestPaths(s, at[e]);
      const bool back = sp.held.holding() || e == home_[sp.robot];
      for (VertexId x : sp.exits) {
        if (x == e || !std::isfinite(tree.dist[at[x]])) continue;
        const double length = tree.dist[at[x]];
        addMove(sp.robot, sp.held, e, x, length, [&] { return roadmap.pathTo(s, tree, at[x]); }, false);
        if (!back || std::binary_search(sp.entries.begin(), sp.entries.end(), x)) continue;
        const auto known = move_of_.find(std::make_pair(x.value(), e.value()));
        if (known != move_of_.end() && !(length < moves_[known->second].length - 1e-12)) continue;
        std::vector<JointVector> path = roadmap.pathTo(s, tree, at[x]);
        std::reverse(path.begin(), path.end());
        backs.push_back({sp.robot, sp.held, x, e, std::move(path), length, true});
      }
    }
  }
  for (MovePath& m : backs) addMove(m.robot, m.held, m.from, m.to, m.length, [&] { return std::move(m.path); }, true);
}

VertexId MotionHypergraph::objectVertex(int object, int placement) const {
  MotionVertex v;
  v.kind = MotionVertex::Kind::kObject;
  v.object = i16(object);
  v.placement = i16(placement);
  return graph_.find(v).value_or(VertexId());
}

std::string MotionHypergraph::label(VertexId id) const {
  const MotionVertex& v = graph_.property(id);
  const Scene& scene = space_->scene();
  switch (v.kind) {
    case MotionVertex::Kind::kSource: return "source";
    case MotionVertex::Kind::kSink: return "sink";
    case MotionVertex::Kind::kRobot: return scene.robots[v.robot].id + "@c" + std::to_string(v.config);
    case MotionVertex::Kind::kHolding:
      return scene.robots[v.robot].id + "+" + scene.objects[v.object].id + "#g" + std::to_string(v.grasp) + "@c" +
             std::to_string(v.config);
    case MotionVertex::Kind::kObject: return space_->locationLabel(v.object, v.placement);
    case MotionVertex::Kind::kTaskPending: return "inspect#" + std::to_string(v.task) + " pending";
    case MotionVertex::Kind::kTaskDone: return "inspect#" + std::to_string(v.task) + " done";
  }
  return "?";
}

std::string MotionHypergraph::label(HyperarcId id) const {
  const MotionArc& a = graph_.property(id);
  std::string s = motionArcTypeName(a.type);
  s += " [";
  bool first = true;
  for (VertexId v : graph_.tail(id)) {
    s += (first ? "" : ", ") + label(v);
    first = false;
  }
  s += "] -> [";
  first = true;
  for (VertexId v : graph_.head(id)) {
    s += (first ? "" : ", ") + label(v);
    first = false;
  }
  return s + "]";
}

}  // namespace dash
