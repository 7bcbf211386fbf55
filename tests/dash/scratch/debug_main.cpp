#include <map>
#include <string>
#include <cstdio>
#include "engine/dash/combined_query.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/core/stopwatch.h"
#include "engine/scene/scene_json.h"
#include "engine/task/geometric_reachability.h"
using namespace dash;
int main(int argc, char** argv) {
  const Scene scene = loadScene(argv[1], RobotLibrary::loadDefault());
  seedOmplOnce(1);
  CollisionWorld world(scene); CollisionContext ctx(world); TaskSpace space(scene);
  TransitionSampler sampler(world, ctx); GeometricReachability reach(sampler);
  Stopwatch sw;
  auto tg = buildDashTaskGraph(space, reach.oracle());
  std::printf("H_T %zu/%zu  %.2fs checks %lu\n", tg.vertexCount(), tg.hyperarcCount(), sw.seconds(), ctx.counters().configuration_checks);
  TransitionCatalogParams tp; if (argc > 3) tp.grasps_per_class = atoi(argv[3]); auto cat = sampleTransitions(sampler, space, tg, tp, Deadline());
  std::printf("catalog grasps %zu handovers %zu  %.2fs checks %lu\n", cat.grasps.size(), cat.handovers.size(), sw.seconds(), ctx.counters().configuration_checks);
  log::EventEmitter em(nullptr);
  MotionHypergraph hm(space, cat, em);
  RoadmapSet rms;
  int n = argc > 2 ? atoi(argv[2]) : 150;
  for (int r = 0; r < world.robotCount(); ++r) for (int h = 0; h < 2; ++h) { rms.push_back(std::make_unique<ValidatedRoadmap>(world, ctx, r)); rms.back()->growTo(h ? n*2/3 : n, Deadline()); 
    std::printf(" roadmap r%d h%d: %zu milestones %zu edges %.2fs checks %lu\n", r, h, rms.back()->milestoneCount(), rms.back()->edgeCount(), sw.seconds(), ctx.counters().configuration_checks); }
  hm.connectMoves(rms, {}, Deadline());
  std::printf("H_M %zu/%zu  %.2fs checks %lu\n", hm.graph().vertexCount(), hm.graph().hyperarcCount(), sw.seconds(), ctx.counters().configuration_checks);
  for (auto& r : rms) std::printf("  rm r%d spaces %zu V %zu E %zu\n", r->robot(), r->spaceCount(), r->vertexCount(), r->edgeCount());
  CombinedQuery q(hm);
  for (int r = 0; r < world.robotCount(); ++r) { auto h = hm.homeVertex(r); std::printf("home r%d out %zu\n", r, hm.graph().outgoing(h).size()); }
  { const auto& g = hm.graph();
    std::map<std::string,int> cnt;
    for (auto a : g.hyperarcs()) cnt[motionArcTypeName(g.property(a).type)]++;
    for (auto& [k,v] : cnt) std::printf("  arcs %s: %d\n", k.c_str(), v);
    if (getenv("CTG")) for (auto v : g.vertices()) { auto& mv = g.property(v); if (mv.kind==MotionVertex::Kind::kObject || mv.kind==MotionVertex::Kind::kHolding) std::printf("  ctg %-40s %g  out %zu in %zu\n", hm.label(v).c_str(), q.costToGo(v), g.outgoing(v).size(), g.incoming(v).size()); }
  }
  auto res = q.run({}, {}, Deadline(60));
  std::printf("query %s exp %zu back %zu steps %zu %.2fs\n", std::string(toString(res.status)).c_str(), res.stats.expansions, res.stats.backtracks, res.steps.size(), sw.seconds());
  for (auto& s : res.steps) std::printf("  %s\n", hm.label(s.hyperarc).c_str());
}
