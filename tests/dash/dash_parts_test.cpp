// The layers of the DaSH baseline one by one, on a two-robot sorting scene.
#include <gtest/gtest.h>

#include <unordered_set>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/dash/combined_query.h"
#include "engine/dash/dash_task_graph.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/plan_extraction.h"
#include "engine/events/memory_sink.h"
#include "engine/motion/lazy_roadmap.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/robots/kinematics.h"
#include "engine/task/geometric_reachability.h"
#include "engine/task/task_hypergraph.h"
#include "tests/dash/dash_built.h"

namespace dash {
namespace {

using test::Built;
using test::sorting22;
using test::sorting22WithMotion;

TEST(DashTaskGraph, ObjectElementsAreLocationFree) {
  const Built& b = sorting22();
  int objects = 0;
  for (VertexId v : b.task_graph.vertices()) {
    const TaskElement& e = b.task_graph.property(v);
    if (e.kind != ElementKind::kObjectAt) continue;
    ++objects;
    EXPECT_EQ(e.location, -1);
  }
  EXPECT_EQ(objects, static_cast<int>(b.scene.objects.size()));
  // Lazy-DaSH's H_T keeps a start and a goal element per object: DaSH's is smaller.
  TaskHypergraph lazy;
  GeometricReachability reach(const_cast<TransitionSampler&>(b.sampler));
  lazy.build(b.space, reach.oracle());
  EXPECT_LT(b.task_graph.vertexCount(), lazy.graph().vertexCount());
  int picks = 0, places = 0, handovers = 0;
  for (HyperarcId a : b.task_graph.hyperarcs()) {
    const TaskArc& arc = b.task_graph.property(a);
    picks += arc.type == TaskArcType::kPick;
    places += arc.type == TaskArcType::kPlace;
    handovers += arc.type == TaskArcType::kHandover;
  }
  EXPECT_GT(picks, 0);
  EXPECT_EQ(picks, places);
  EXPECT_GT(handovers, 0);  // cross sorting with two robots needs one handover per object
}

TEST(DashTransitions, EveryConfigurationIsStaticallyFreeAndGraspsTheObject) {
  Built& b = sorting22();
  ASSERT_FALSE(b.catalog.grasps.empty());
  ASSERT_FALSE(b.catalog.handovers.empty());
  const ObjectLayout none = ObjectLayout::empty(b.scene);
  for (const GraspSample& g : b.catalog.grasps) {
    const SceneRobot& r = b.scene.robots[g.robot];
    const Pose X_WT = forwardKinematics(*r.model, r.X_WB, g.q).X_WT;
    const Pose& X_WO = b.space.location(g.object, g.placement).X_WO;
    EXPECT_LT(translationDistance(X_WT * g.held.X_TO, X_WO), 1e-6);
    EXPECT_FALSE(robotInCollision(b.world, b.context, {g.robot, g.q, g.held}, none));
    EXPECT_FALSE(robotInCollision(b.world, b.context, {g.robot, g.q_pre, {}}, none));
    EXPECT_FALSE(robotInCollision(b.world, b.context, {g.robot, g.q_hold, g.held}, none));
  }
  for (const HandoverSample& h : b.catalog.handovers) {
    const RobotState both[2] = {{h.giver, h.q1, h.held}, {h.receiver, h.q2, {}}};
    EXPECT_FALSE(robotsInCollision(b.world, b.context, both, none, nullptr, CheckScope::kStaticOnly));
    const SceneRobot& g = b.scene.robots[h.giver];
    const SceneRobot& r = b.scene.robots[h.receiver];
    EXPECT_LT(translationDistance(forwardKinematics(*g.model, g.X_WB, h.q1).X_WT * h.held.X_TO, h.X_WO), 1e-6);
    EXPECT_LT(translationDistance(forwardKinematics(*r.model, r.X_WB, h.q2).X_WT * h.held2.X_TO, h.X_WO), 1e-6);
    EXPECT_TRUE(handoverClassesCompatible(h.grasp, h.grasp2));
  }
}

TEST(ValidatedRoadmap, PathsAreValidAndPlanAvoidsRestingObjects) {
  Built& b = sorting22();
  ValidatedRoadmap roadmap(b.world, b.context, 0);
  roadmap.growTo(80, Deadline());
  EXPECT_EQ(roadmap.milestoneCount(), 80u);
  const int s = roadmap.space({});
  const GraspSample* g = nullptr;
  for (const GraspSample& c : b.catalog.grasps)
    if (c.robot == 0) g = &c;
  ASSERT_NE(g, nullptr);
  const JointVector& home = b.scene.robots[0].home;
  const int a = roadmap.anchor(s, home);
  const int z = roadmap.anchor(s, g->q_pre);
  EXPECT_EQ(roadmap.anchor(s, home), a);  // the same configuration is the same vertex
  const auto tree = roadmap.shortestPaths(s, a);
  const auto path = roadmap.pathTo(s, tree, z);
  ASSERT_GE(path.size(), 2u);
  EXPECT_EQ(path.front(), home);
  EXPECT_EQ(path.back(), g->q_pre);
  const ObjectLayout none = ObjectLayout::empty(b.scene);
  for (std::size_t i = 1; i < path.size(); ++i)
    EXPECT_FALSE(segmentInCollision(b.world, b.context, {0, path[i - 1], {}}, path[i], none));
  // With every object resting at its start, plan() returns a path free of them too (or none).
  MotionContext ctx{{}, ObjectLayout::atStart(b.scene), {}};
  if (auto p = roadmap.plan(home, g->q_pre, ctx, Deadline())) {
    for (std::size_t i = 1; i < p->size(); ++i)
      EXPECT_FALSE(segmentInCollision(b.world, b.context, {0, (*p)[i - 1], {}}, (*p)[i], ctx.layout));
  }
}

TEST(MotionHypergraph, ExhaustiveMovesWithinOnePlanningSpaceAndEveryElementAnEvent) {
  Built& b = sorting22();
  log::MemorySink sink;
  log::EventEmitter emitter(&sink);
  b.buildMotion(emitter);
  const MotionGraph& g = b.motion->graph();
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Vertex), static_cast<std::int64_t>(g.vertexCount()));
  EXPECT_EQ(sink.count(log::Layer::Motion, log::ElementKind::Hyperarc), static_cast<std::int64_t>(g.hyperarcCount()));
  int moves = 0, picks = 0;
  for (HyperarcId a : g.hyperarcs()) {
    const MotionArc& arc = g.property(a);
    if (arc.type == MotionArc::Type::kPick) ++picks;
    if (arc.type != MotionArc::Type::kMove) continue;
    ++moves;
    const MovePath& m = b.motion->move(arc.index);
    const MotionVertex& from = g.property(g.tail(a).front());
    const MotionVertex& to = g.property(g.head(a).front());
    EXPECT_EQ(from.robot, m.robot);
    EXPECT_EQ(to.robot, m.robot);
    EXPECT_EQ(from.kind, to.kind);     // one hand state per planning space
    EXPECT_EQ(from.object, to.object);
    EXPECT_EQ(from.grasp, to.grasp);
    EXPECT_EQ(m.path.front(), b.motion->config(from.config));
    EXPECT_EQ(m.path.back(), b.motion->config(to.config));
    EXPECT_NEAR(b.motion->cost(a), m.length, 1e-9);
  }
  EXPECT_EQ(picks, static_cast<int>(b.catalog.grasps.size()));
  // Every transition joined to every other in each space: far more moves than transitions.
  EXPECT_GT(moves, 2 * picks);
}

// A robot at a handover's waiting configuration (no transition but that handover leaves from there)
// can leave when its partner does not come: empty-handed back home, holding back to a configuration
// where it took the object. Without these moves a receiver that went to wait for an object another
// robot then placed elsewhere could never get home (wall 8/2/16 seed 9 ended "no hyperpath").
TEST(MotionHypergraph, ARobotWaitingForAHandoverCanLeave) {
  Built& b = sorting22WithMotion();
  const MotionGraph& g = b.motion->graph();
  auto movesOut = [&](VertexId v, VertexId to) {
    int n = 0;
    for (HyperarcId a : g.outgoing(v))
      n += g.property(a).type == MotionArc::Type::kMove && (!to.valid() || g.head(a).front() == to);
    return n;
  };
  auto movesIn = [&](VertexId v) {
    int n = 0;
    for (HyperarcId a : g.incoming(v)) n += g.property(a).type == MotionArc::Type::kMove;
    return n;
  };
  int handovers = 0, waits_checked = 0;
  for (HyperarcId a : g.hyperarcs()) {
    if (g.property(a).type != MotionArc::Type::kHandover) continue;
    ++handovers;
    for (VertexId v : g.tail(a)) {
      const MotionVertex& mv = g.property(v);
      if (movesIn(v) == 0) continue;  // a configuration the roadmap did not connect
      ++waits_checked;
      if (mv.kind == MotionVertex::Kind::kRobot) EXPECT_EQ(movesOut(v, b.motion->homeVertex(mv.robot)), 1) << b.motion->label(v);
      else EXPECT_GE(movesOut(v, {}), 1) << b.motion->label(v);
    }
  }
  EXPECT_GT(handovers, 0);
  EXPECT_GT(waits_checked, 0);
}

TEST(CombinedQuery, FindsAHyperpathAndHonoursMotionConstraints) {
  Built& b = sorting22WithMotion();
  CombinedQuery query(*b.motion);
  const HyperpathResult first = query.run({}, {}, Deadline());
  ASSERT_TRUE(first.found()) << toString(first.status);
  const ExtractedPlan plan = extractPlan(*b.motion, first);
  int picks = 0, places = 0;
  for (const TaskStep& s : plan.plan.steps) {
    picks += s.action.type == TaskArcType::kPick;
    places += s.action.type == TaskArcType::kPlace;
    for (int d : s.after) EXPECT_LT(d, static_cast<int>(&s - plan.plan.steps.data()));
  }
  EXPECT_EQ(picks, 2);
  EXPECT_EQ(places, 2);
  // Each robot's visits chain: a transit starts where the previous retreat ended.
  for (const RobotMotionPlan& r : plan.motion.robots)
    for (std::size_t i = 1; i < r.visits.size(); ++i) EXPECT_EQ(r.visits[i].transit.front(), r.visits[i - 1].q_post);
  // Forbid the first move hyperarc used: the next hyperpath avoids it.
  HyperarcId used;
  for (const HyperpathStep& s : first.steps)
    if (b.motion->graph().property(s.hyperarc).type == MotionArc::Type::kMove) {
      used = s.hyperarc;
      break;
    }
  ASSERT_TRUE(used.valid());
  const MotionConstraint never{b.motion->moveRobot(used), {}, used, {}};
  const HyperpathResult second = query.run({never}, {}, Deadline());
  ASSERT_TRUE(second.found());
  for (const HyperpathStep& s : second.steps) EXPECT_NE(s.hyperarc, used);
}

// A hand-built case the greedy pass misses: robot r may leave home only for configurations where
// nothing can happen at the start (a pick at an object's goal, empty until r brings it there). The
// greedy order never expands such a move, so its pass exhausts its states; the only way is a detour
// through such a configuration, which the complete pass finds.
TEST(CombinedQuery, CompletePassFindsTheDetourTheGreedyPassMisses) {
  Built& b = sorting22WithMotion();
  const MotionGraph& g = b.motion->graph();
  const int r = 0;
  const VertexId home = b.motion->homeVertex(r);
  // A head is idle at the start when every transition from it is a pick of an object away from its start.
  auto idleAtStart = [&](VertexId v) {
    const auto& transitions = b.motion->transitionsFrom(v);
    if (transitions.empty()) return false;
    for (HyperarcId t : transitions) {
      if (g.property(t).type != MotionArc::Type::kPick) return false;
      for (VertexId u : g.tail(t)) {
        const MotionVertex& mv = g.property(u);
        if (mv.kind == MotionVertex::Kind::kObject && mv.placement == b.space.startLocation(mv.object)) return false;
      }
    }
    return true;
  };
  std::vector<MotionConstraint> constraints;
  std::vector<VertexId> idle_heads;
  for (HyperarcId a : g.outgoing(home)) {
    if (g.property(a).type != MotionArc::Type::kMove) continue;
    const VertexId to = g.head(a).front();
    if (idleAtStart(to)) idle_heads.push_back(to);
    else constraints.push_back({r, {}, a, {}});
  }
  ASSERT_FALSE(idle_heads.empty());
  ASSERT_FALSE(constraints.empty());
  CombinedQuery query(*b.motion);
  CombinedQueryParams greedy_only;
  greedy_only.one_object_pass = false;
  greedy_only.complete_pass = false;
  const HyperpathResult greedy = query.run(constraints, greedy_only, Deadline());
  EXPECT_EQ(greedy.status, HyperpathStatus::kExhausted);
  CombinedQueryParams complete_after_greedy;
  complete_after_greedy.one_object_pass = false;
  const HyperpathResult complete = query.run(constraints, complete_after_greedy, Deadline());
  ASSERT_TRUE(complete.found()) << toString(complete.status);
  EXPECT_EQ(query.lastPass(), CombinedQuery::Pass::kComplete);
  bool detour = false;
  for (const HyperpathStep& s : complete.steps) {
    for (const MotionConstraint& c : constraints) EXPECT_NE(s.hyperarc, c.edge);
    if (g.property(s.hyperarc).type == MotionArc::Type::kMove && g.tail(s.hyperarc).front() == home &&
        idleAtStart(g.head(s.hyperarc).front()))
      detour = true;
  }
  EXPECT_TRUE(detour);
  // DaSH as published (greedy_move_pruning off, no other pass): the one greedy pass expands every move
  // and is complete by itself, so it finds the detour alone.
  CombinedQueryParams unpruned;
  unpruned.prune_moves = false;
  unpruned.one_object_pass = false;
  unpruned.complete_pass = false;
  const HyperpathResult alone = query.run(constraints, unpruned, Deadline());
  EXPECT_TRUE(alone.found()) << toString(alone.status);
  EXPECT_EQ(query.lastPass(), CombinedQuery::Pass::kComplete);
  // The hyperpath still extracts to a plan whose robots' visits chain.
  const ExtractedPlan plan = extractPlan(*b.motion, complete);
  for (const RobotMotionPlan& rp : plan.motion.robots)
    for (std::size_t i = 1; i < rp.visits.size(); ++i) EXPECT_EQ(rp.visits[i].transit.front(), rp.visits[i - 1].q_post);
}

// A place whose empty-handed retreat has no move anywhere (a roadmap that did not connect it) strands
// its robot: the goal needs every robot home, and re-picking the object from its goal only undoes the
// place. Such a step is never taken, so the query neither descends into states that cannot end nor
// counts it as a route for the object.
TEST(CombinedQuery, AStepThatLeavesARobotNoWayHomeIsNeverTaken) {
  Built& b = sorting22WithMotion();
  const MotionGraph& g = b.motion->graph();
  CombinedQuery query(*b.motion);
  const HyperpathResult first = query.run({}, {}, Deadline());
  ASSERT_TRUE(first.found());
  HyperarcId place;
  // The first place that puts its object at its goal (a place elsewhere can be undone by a pick,
  // which is a way home).
  auto placesAtGoal = [&](HyperarcId a) {
    if (g.property(a).type != MotionArc::Type::kPlace) return false;
    for (VertexId h : g.head(a)) {
      const MotionVertex& hv = g.property(h);
      if (hv.kind == MotionVertex::Kind::kObject && hv.placement == b.space.goalLocation(hv.object)) return true;
    }
    return false;
  };
  for (const HyperpathStep& s : first.steps) {
    EXPECT_FALSE(query.strandsRobot(s.hyperarc));
    if (!place.valid() && placesAtGoal(s.hyperarc)) place = s.hyperarc;
  }
  ASSERT_TRUE(place.valid());
  VertexId retreat;
  for (VertexId v : g.head(place))
    if (g.property(v).kind == MotionVertex::Kind::kRobot) retreat = v;
  ASSERT_TRUE(retreat.valid());
  const int r = g.property(retreat).robot;
  // Every move out of the retreat forbidden: the robot can leave it only by picking the object again.
  std::vector<MotionConstraint> constraints;
  for (HyperarcId a : g.outgoing(retreat))
    if (g.property(a).type == MotionArc::Type::kMove) constraints.push_back({r, {}, a, {}});
  ASSERT_FALSE(constraints.empty());
  const HyperpathResult second = query.run(constraints, {}, Deadline());
  EXPECT_TRUE(query.strandsRobot(place));
  // Through another grasp where H_M has one; where it has none (since approaches and retreats are
  // Cartesian-dense, sorting 2/2's H_M holds one grasp chain per object that reaches the goal), the
  // query ends exhausted rather than return a hyperpath through the stranding place.
  if (!second.found()) {
    EXPECT_EQ(second.status, HyperpathStatus::kExhausted) << toString(second.status);
  }
  for (const HyperpathStep& s : second.steps) {
    EXPECT_NE(s.hyperarc, place);
    EXPECT_FALSE(query.strandsRobot(s.hyperarc));
  }
  query.run({}, {}, Deadline());
  EXPECT_FALSE(query.strandsRobot(place));
  // stranding_prune off (DaSH as published): no step is ruled out for where it leaves a robot.
  CombinedQueryParams unpruned;
  unpruned.stranding_prune = false;
  query.run(constraints, unpruned, Deadline());
  EXPECT_FALSE(query.strandsRobot(place));
}

// When the greedy pass gives up (here: a budget of one state), the next pass moves one object at a
// time: every step that moves an object moves the first one not yet at its goal, so objects finish in
// index order, and robots still go wherever that object's route needs them.
TEST(CombinedQuery, TheOneObjectPassFinishesObjectsInOrder) {
  Built& b = sorting22WithMotion();
  const MotionGraph& g = b.motion->graph();
  CombinedQuery query(*b.motion);
  CombinedQueryParams params;
  params.max_expansions = 1;
  const HyperpathResult path = query.run({}, params, Deadline());
  ASSERT_TRUE(path.found()) << toString(path.status);
  EXPECT_EQ(query.lastPass(), CombinedQuery::Pass::kOneObjectAtATime);
  int current = 0, object_steps = 0;
  for (const HyperpathStep& s : path.steps) {
    const MotionArc::Type type = g.property(s.hyperarc).type;
    if (type != MotionArc::Type::kPick && type != MotionArc::Type::kPlace && type != MotionArc::Type::kHandover)
      continue;
    int object = -1;
    for (VertexId v : g.head(s.hyperarc))
      if (g.property(v).object >= 0) object = g.property(v).object;
    ++object_steps;
    EXPECT_GE(object, current) << "object " << object << " moved after object " << current << " started";
    current = std::max(current, object);
  }
  EXPECT_EQ(current, 1);  // both objects moved, the second after the first
  EXPECT_GE(object_steps, 4);
}

// A constraint with an interval: robot r kept off a vertex only while an object rests at its start.
TEST(MotionConstraint, AnIntervalHoldsOnlyWhileItsVertexIsOnTheFrontier) {
  Built& b = sorting22WithMotion();
  CombinedQuery query(*b.motion);
  const HyperpathResult first = query.run({}, {}, Deadline());
  ASSERT_TRUE(first.found());
  const MotionGraph& g = b.motion->graph();
  // The first pick: its robot's entry vertex, while the object rests at its start.
  for (const HyperpathStep& s : first.steps) {
    if (g.property(s.hyperarc).type != MotionArc::Type::kPick) continue;
    MotionConstraint c;
    for (VertexId v : g.tail(s.hyperarc)) {
      const MotionVertex& mv = g.property(v);
      if (mv.kind == MotionVertex::Kind::kObject) c.while_resting = v;
      if (mv.kind == MotionVertex::Kind::kRobot) {
        c.vertex = v;
        c.robot = mv.robot;
      }
    }
    ASSERT_TRUE(c.vertex.valid() && c.while_resting.valid());
    const HyperpathResult second = query.run({c}, {}, Deadline());
    // Sorting 2/2's H_M has one grasp chain per object that reaches its goal (approaches are
    // Cartesian-dense): with that pick ruled out the query may end exhausted, never through the pick.
    if (!second.found()) {
      EXPECT_EQ(second.status, HyperpathStatus::kExhausted) << toString(second.status);
    }
    for (const HyperpathStep& t : second.steps) {
      // The constrained pick (robot at the vertex while the object rests there) never happens.
      EXPECT_NE(t.hyperarc, s.hyperarc);
    }
    EXPECT_TRUE(describe(*b.motion, c).find("while") != std::string::npos);
    return;
  }
  FAIL() << "no pick in the first hyperpath";
}

}  // namespace
}  // namespace dash
