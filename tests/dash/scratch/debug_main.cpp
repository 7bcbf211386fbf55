#include <map>
#include <string>
#include <cstdio>
#include "engine/dash/combined_query.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/placement_sampling.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/core/stopwatch.h"
#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/scene/scene_json.h"
#include "engine/task/geometric_reachability.h"
using namespace dash;
int main(int argc, char** argv) {
  const Scene scene = loadScene(argv[1], RobotLibrary::loadDefault());
  seedOmplOnce(1);
  CollisionWorld world(scene); CollisionContext ctx(world); TaskSpace space(scene);
  TransitionSampler sampler(world, ctx); GeometricReachability reach(sampler);
  Stopwatch sw;
  if (getenv("PRESAMPLE")) { Rng rng(Rng::derive(1, 23)); presamplePlacements(space, reach, sampler, rng, {}); for (int o = 0; o < space.objectCount(); ++o) for (int l = 0; l < (int)space.locations(o).size(); ++l) { auto p = space.location(o,l).X_WO.translation(); std::printf("  loc %s (%.3f %.3f %.3f)\n", space.locationLabel(o,l).c_str(), p.x(), p.y(), p.z()); } }
  if (getenv("LAB")) { double x = 0.095; for (const auto& t : scene.tasks) if (t.requires_removed_object >= 0) { Pose X = scene.objects[t.requires_removed_object].X_WO_start; X.translation() = Vec3(x, 0.154, 0.125); x += 0.1; space.addExtraLocation(t.requires_removed_object, X, 1); } }
  auto tg = buildDashTaskGraph(space, reach.oracle());
  std::printf("H_T %zu/%zu  %.2fs checks %lu\n", tg.vertexCount(), tg.hyperarcCount(), sw.seconds(), ctx.counters().configuration_checks);
  TransitionCatalogParams tp; if (argc > 3) tp.grasps_per_class = atoi(argv[3]); if (getenv("HP")) tp.handover_poses = atoi(getenv("HP")); auto cat = sampleTransitions(sampler, space, tg, tp, Deadline());
  std::printf("catalog grasps %zu handovers %zu  %.2fs checks %lu\n", cat.grasps.size(), cat.handovers.size(), sw.seconds(), ctx.counters().configuration_checks);
  { ObjectLayout none = ObjectLayout::empty(scene); int bad[5] = {0,0,0,0,0};
    for (auto& h : cat.handovers) {
      RobotState a{h.giver, h.q1, h.held}, b{h.receiver, h.q2_pre, {}};
      RobotState s2[2] = {a, b};
      bool b0 = robotsInCollision(world, ctx, s2, none, nullptr, CheckScope::kStaticOnly);
      std::vector<RobotMotion> m1{{RobotState{h.receiver, h.q2_pre, {}}, h.q2}, {a, h.q1}};
      bool b1 = motionsInCollision(world, ctx, m1, none);
      std::vector<RobotMotion> m2{{RobotState{h.receiver, h.q2, h.held2}, h.q2}, {RobotState{h.giver, h.q1, {}}, h.q1_post}};
      bool b2 = motionsInCollision(world, ctx, m2, none);
      std::vector<RobotMotion> m3{{RobotState{h.receiver, h.q2, h.held2}, h.q2_post}, {RobotState{h.giver, h.q1_post, {}}, h.q1_post}};
      bool b3 = motionsInCollision(world, ctx, m3, none);
      bad[0]+=b0; bad[1]+=b1; bad[2]+=b2; bad[3]+=b3;
      std::printf("  ho %d->%d o%d %s->%s  pre %d approach %d giverRetreat %d recvRetreat %d  pre2==q2 %d post1==q1 %d\n", h.giver, h.receiver, h.object, graspClassName(h.grasp), graspClassName(h.grasp2), b0, b1, b2, b3, (h.q2_pre-h.q2).norm()<1e-9, (h.q1_post-h.q1).norm()<1e-9);
    }
  }
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
