#pragma once
// Shared by the tests of engine/tpg: a sorting scene (scenario seed 1), its Lazy-DaSH plan (seed 1)
// and the plan's temporal plan graph.
#include <memory>
#include <string>

#include "engine/planners/planner.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/tpg/tpg.h"

namespace dash::tpg {

/// A sorting scene, its Lazy-DaSH plan (seed 1) and the plan's graph.
struct Case {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Plan> plan;
  std::unique_ptr<Graph> graph;
};

inline Case planAndBuild(const std::shared_ptr<const RobotLibrary>& library, const std::string& robots,
                  const std::string& objects) {
  Case c;
  c.scene = std::make_unique<Scene>(generateScenario("sorting", {{"robots", robots}, {"objects", objects}}, 1, library));
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = 120;
  PlanResult result = makePlanner("lazy-dash")->solve(*c.scene, settings, Deadline(settings.time_limit), nullptr);
  if (result.outcome != PlanOutcome::kSolved) return c;
  c.plan = std::make_unique<Plan>(*result.plan);
  c.graph = std::make_unique<Graph>(buildGraph(*c.scene, *c.plan));
  return c;
}

inline int countEdges(const Graph& graph, Edge::Why why) {
  int n = 0;
  for (const Edge& e : graph.edges) n += e.why == why;
  return n;
}

}  // namespace dash::tpg
