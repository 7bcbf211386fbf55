#pragma once
// A scene built up to DaSH's motion hypergraph, as DashPlanner builds it, for the tests of DaSH's
// parts (dash_parts_test.cpp, cbs_mp_constraint_test.cpp). Each test executable has its own copy of
// one copy of the scenes below (built once, by whichever test needs them first).
#include <memory>

#include "engine/dash/dash_task_graph.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/events/event_emitter.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/task/geometric_reachability.h"
#include "tests/dash/dash_test_util.h"

namespace dash::test {

// Everything up to the motion hypergraph for one scene, as DashPlanner builds it (no pre-sampled
// placements: the tests below count elements).
struct Built {
  explicit Built(Scene s) : scene(std::move(s)), world(scene), context(world), space(scene), sampler(world, context),
                            reach(sampler) {
    task_graph = buildDashTaskGraph(space, reach.oracle());
    catalog = sampleTransitions(sampler, space, task_graph, {}, Deadline());
  }
  void buildMotion(log::EventEmitter& emitter) {
    motion = std::make_unique<MotionHypergraph>(space, catalog, emitter);
    roadmaps = RoadmapSet(world.robotCount());
    for (int r = 0; r < world.robotCount(); ++r)
      for (const bool holding : {false, true}) {
        roadmaps.slot(r, holding) = std::make_unique<ValidatedRoadmap>(world, context, r);
        roadmaps.at(r, holding).growTo(60, Deadline());
      }
    motion->connectMoves(roadmaps, {}, Deadline());
  }

  const OmplSeedScope ompl_seeds{1};  // the roadmaps' samples: from seed 1, whatever ran before
  Scene scene;
  CollisionWorld world;
  CollisionContext context;
  TaskSpace space;
  TransitionSampler sampler;
  GeometricReachability reach;
  DashTaskGraph task_graph;
  TransitionCatalog catalog;
  std::unique_ptr<MotionHypergraph> motion;
  RoadmapSet roadmaps;
};

inline Built& sorting22() {
  static Built built(dashScene("sorting", {{"robots", "2"}, {"objects", "2"}}));
  return built;
}

/// sorting22() with its motion hypergraph (built once, by whichever test needs it first).
inline Built& sorting22WithMotion() {
  Built& b = sorting22();
  if (!b.motion) {
    log::EventEmitter emitter(nullptr);
    b.buildMotion(emitter);
  }
  return b;
}

}  // namespace dash::test
