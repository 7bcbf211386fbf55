#pragma once
// A task-like hypergraph at the paper's scale, for tests and timing: robots in a row, objects that
// start near one robot and must end near the mirrored one (cross sorting), pick and place at both sites, handovers between
// robots a few places apart, several grasps per held object.
#include <algorithm>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include "engine/hypergraph/hypergraph.h"
#include "engine/hypergraph/hyperpath_search.h"

namespace dash::testing {

struct Element {
  enum Kind { kSource, kSink, kRobot, kObjectStart, kObjectGoal, kHeld } kind;
  int robot = -1;
  int object = -1;
  int grasp = -1;
  bool operator==(const Element&) const = default;
};

}  // namespace dash::testing

template <>
struct std::hash<dash::testing::Element> {
  std::size_t operator()(const dash::testing::Element& e) const noexcept {
    const long long key = ((static_cast<long long>(e.kind) * 64 + e.robot + 1) * 1024 + e.object + 1) * 16 + e.grasp + 1;
    return std::hash<long long>{}(key);
  }
};

namespace dash::testing {

struct TaskLike {
  Hypergraph<Element, std::string> graph;
  HyperpathQuery query;
  std::vector<double> costToGo;  // per vertex: steps left with unit costs
  int objects = 0;
};

inline TaskLike buildTaskLike(int robots, int objects, int grasps, int handoverReach) {
  TaskLike t;
  t.objects = objects;
  auto& g = t.graph;
  auto startRobot = [&](int k) { return k % robots; };
  auto goalRobot = [&](int k) { return robots - 1 - startRobot(k); };  // cross sorting: the far side
  auto reaches = [&](int r, int site) { return std::abs(r - site) <= 1; };
  std::vector<VertexId> robot(robots);
  for (int r = 0; r < robots; ++r) robot[r] = g.addVertex({Element::kRobot, r}).id;
  std::vector<VertexId> starts, goals;
  for (int k = 0; k < objects; ++k) {
    starts.push_back(g.addVertex({Element::kObjectStart, -1, k}).id);
    goals.push_back(g.addVertex({Element::kObjectGoal, -1, k}).id);
  }
  auto held = [&](int r, int k, int q) { return g.addVertex({Element::kHeld, r, k, q}).id; };
  for (int k = 0; k < objects; ++k) {
    for (int r = 0; r < robots; ++r) {
      for (int q = 0; q < grasps; ++q) {
        const VertexId h = held(r, k, q);
        if (reaches(r, startRobot(k))) {
          g.addHyperarc({robot[r], starts[k]}, {h}, "pick");
          g.addHyperarc({h}, {robot[r], starts[k]}, "place");
        }
        if (reaches(r, goalRobot(k))) {
          g.addHyperarc({robot[r], goals[k]}, {h}, "pick");
          g.addHyperarc({h}, {robot[r], goals[k]}, "place");
        }
        for (int s = std::max(0, r - handoverReach); s <= std::min(robots - 1, r + handoverReach); ++s) {
          if (s == r) continue;
          for (int q2 = 0; q2 < grasps; ++q2) g.addHyperarc({h, robot[s]}, {robot[r], held(s, k, q2)}, "handover");
        }
      }
    }
  }
  const VertexId src = g.addVertex({Element::kSource}).id, sink = g.addVertex({Element::kSink}).id;
  std::vector<VertexId> initial(robot.begin(), robot.end());
  initial.insert(initial.end(), starts.begin(), starts.end());
  t.query.source = g.addHyperarc({src}, initial, "source").id;
  t.query.sink = g.addHyperarc(goals, {sink}, "sink").id;

  // Handovers to come within reach of the goal robot, then the place.
  auto heldCost = [&](int r, int k) {
    const int gap = std::max(0, std::abs(r - goalRobot(k)) - 1);
    return 1.0 + (gap + handoverReach - 1) / handoverReach;
  };
  t.costToGo.assign(g.vertexCount(), 0.0);
  for (VertexId v : g.vertices()) {
    const Element& e = g.property(v);
    if (e.kind == Element::kHeld) t.costToGo[v.value()] = heldCost(e.robot, e.object);
    if (e.kind == Element::kObjectStart) {
      double best = 1e9;
      for (int r = 0; r < robots; ++r)
        if (reaches(r, startRobot(e.object))) best = std::min(best, 1.0 + heldCost(r, e.object));
      t.costToGo[v.value()] = best;
    }
  }
  return t;
}

}  // namespace dash::testing
