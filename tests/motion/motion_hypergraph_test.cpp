// The motion hypergraph H_M: deduplicated across rounds, a handover as one hyperarc coupling both
// robots, H_ME counted from the motion query's own search; and a motion constraint's region respected
// by the next motion query on the same task plan.
#include <gtest/gtest.h>

#include <map>
#include <variant>

#include "engine/events/memory_sink.h"
#include "engine/motion/motion_hypergraph.h"
#include "engine/motion/motion_layer.h"
#include "engine/motion/seeded_ompl.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/task/task_layer.h"
#include "tests/motion/first_task_plan.h"

namespace dash {
namespace {

using lazy::MotionHypergraph;
using lazy::MotionQueryCounts;

JointVector joints(double a) {
  JointVector q(6);
  q << a, 0, 0, 0, 0, 0;
  return q;
}

TEST(MotionHypergraph, AnElementAddedAgainIsTheSameElement) {
  log::EventEmitter emitter(nullptr);
  MotionHypergraph g(emitter);
  const VertexId a = g.robotVertex(0, TaskElement::robotAlone(0), joints(0.1));
  const VertexId b = g.robotVertex(0, TaskElement::robotAlone(0), joints(0.2));
  EXPECT_EQ(g.robotVertex(0, TaskElement::robotAlone(0), joints(0.1)), a);
  EXPECT_NE(g.robotVertex(1, TaskElement::robotAlone(1), joints(0.1)), a);  // another robot
  EXPECT_NE(g.robotVertex(0, TaskElement::holding(0, 0, GraspClass::kTop), joints(0.1)), a);  // another v_T
  const auto m = g.move(a, b, {joints(0.1), joints(0.2)});
  ASSERT_TRUE(m.has_value());
  EXPECT_EQ(g.move(a, b, {joints(0.1), joints(0.15), joints(0.2)}), m);
  EXPECT_EQ(g.path(*m).size(), 3u);  // the last validated path
  EXPECT_FALSE(g.move(a, a, {}).has_value());
  EXPECT_EQ(g.vertexCount(), 4u);
  EXPECT_EQ(g.hyperarcCount(), 1u);
}

TEST(MotionHypergraph, AHandoverIsOneHyperarcCouplingBothRobotsAndEachHyperarcTakenIsOneExtendedHyperarc) {
  log::EventEmitter emitter(nullptr);
  MotionHypergraph g(emitter);
  TaskArc handover;
  handover.type = TaskArcType::kHandover;
  handover.robot = 0;
  handover.robot2 = 1;
  handover.object = 0;
  const VertexId home0 = g.robotVertex(0, TaskElement::robotAlone(0), joints(0));
  const VertexId home1 = g.robotVertex(1, TaskElement::robotAlone(1), joints(0));
  const VertexId obj = g.objectVertex(0, 0, Pose::Identity());
  const VertexId pick_at = g.robotVertex(0, TaskElement::robotAlone(0), joints(0.5));
  const VertexId held = g.robotVertex(0, TaskElement::holding(0, 0, GraspClass::kTop), joints(0.5));
  const VertexId give = g.robotVertex(0, TaskElement::holding(0, 0, GraspClass::kTop), joints(0.9));
  const VertexId given = g.robotVertex(0, TaskElement::robotAlone(0), joints(0.9));
  const VertexId take = g.robotVertex(1, TaskElement::robotAlone(1), joints(0.7));
  const VertexId taken = g.robotVertex(1, TaskElement::holding(1, 0, GraspClass::kTop), joints(0.7));
  const HyperarcId source = g.source({home0, home1, obj});
  TaskArc pick;
  pick.robot = 0;
  pick.object = 0;
  std::vector<HyperarcId> seq{source, *g.move(home0, pick_at, {}), g.transition(pick, {pick_at, obj}, {held}),
                              *g.move(held, give, {}), *g.move(home1, take, {}),
                              g.transition(handover, {give, take}, {given, taken}),
                              // back home and out again to the same place: a vertex revisited
                              *g.move(given, home0, {}), *g.move(home0, pick_at, {})};
  const HyperarcId h = seq[5];
  EXPECT_EQ(g.graph().tail(h).size(), 2u);
  EXPECT_EQ(g.graph().head(h).size(), 2u);
  EXPECT_EQ(g.coupledHyperarcCount(), 1u);
  seq.push_back(g.sink({pick_at, taken}));
  g.beginQuery();
  for (HyperarcId a : seq) g.take(a);
  const MotionQueryCounts counts = g.queryCounts();
  EXPECT_TRUE(counts.reached_sink);
  EXPECT_EQ(counts.extended_hyperarcs, seq.size());
  // The source's 3 instances, then one per head vertex of each hyperarc taken (the sink has none).
  EXPECT_EQ(counts.extended_vertices, 3u + 1 + 1 + 1 + 1 + 2 + 1 + 1);
  // A second query over the same H_M adds to H_ME only; a hyperarc taken twice (a branch left and taken
  // again) is two extended hyperarcs.
  const std::size_t vertices = g.vertexCount(), arcs = g.hyperarcCount();
  g.beginQuery();
  for (HyperarcId a : seq) g.take(a);
  g.take(seq[6]);
  EXPECT_EQ(g.queryCounts().extended_hyperarcs, seq.size() + 1);
  EXPECT_EQ(g.vertexCount(), vertices);
  EXPECT_EQ(g.hyperarcCount(), arcs);
  EXPECT_EQ(g.extendedHyperarcCount(), 2 * seq.size() + 1);
}

using testing::FirstTaskPlan;

/// Motion hyperarcs per type in the event stream, moves left out.
std::map<std::string, std::int64_t> transitionArcCounts(const log::MemorySink& sink) {
  std::map<std::string, std::int64_t> out;
  for (const log::Event& e : sink.events()) {
    const auto* r = std::get_if<log::RepresentationEvent>(&e.payload);
    if (r == nullptr || r->layer != log::Layer::Motion || r->kind != log::ElementKind::Hyperarc) continue;
    if (r->arc_type != "move") out[r->arc_type] += r->change == log::ElementChange::Added ? 1 : -1;
  }
  return out;
}

TEST(MotionLayer, RoundsOnTheSamePlanReuseHMAndCoupleEveryHandover) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("sorting", {{"robots", "4"}, {"objects", "8"}});
  ASSERT_EQ(run.layer.status, TaskLayerStatus::kFeasible) << run.layer.reason;
  int handovers = 0;
  for (const TaskStep& s : run.layer.plan.steps) handovers += s.action.type == TaskArcType::kHandover ? 1 : 0;
  ASSERT_GT(handovers, 0) << "sorting 4/8 hands objects over";
  const MotionLayerResult first = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(first.status, MotionStatus::kOk) << first.reason;
  const std::size_t vertices = run.motion.motionVertices(), arcs = run.motion.motionHyperarcs();
  const std::size_t extended = run.motion.extendedHyperarcs();
  EXPECT_EQ(run.motion.hypergraph().coupledHyperarcCount(), static_cast<std::size_t>(handovers));
  EXPECT_NE(extended, arcs);
  // H_ME: the hyperpath found, the moves found invalid and the retreats backtracked from.
  EXPECT_EQ(extended, first.hyperpath_hyperarcs + first.failed_moves + first.backtracks);
  const std::map<std::string, std::int64_t> transitions_first = transitionArcCounts(run.sink);
  const MotionLayerResult again = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(again.status, MotionStatus::kOk) << again.reason;
  // The same transition configurations: the same vertices and transition hyperarcs, none twice. The
  // roadmap grew between the rounds, so a move may now end at another back-off or pass another via
  // configuration: only moves (and the vertices at their ends) may be added.
  EXPECT_LE(vertices, run.motion.motionVertices());
  EXPECT_EQ(transitionArcCounts(run.sink), transitions_first);
  EXPECT_EQ(run.motion.hypergraph().coupledHyperarcCount(), static_cast<std::size_t>(handovers));
  EXPECT_LE(run.motion.motionVertices() - vertices, vertices / 10) << "a second round on the same plan rebuilt H_M";
  EXPECT_EQ(run.motion.extendedHyperarcs() - extended, again.hyperpath_hyperarcs + again.failed_moves + again.backtracks);
  EXPECT_EQ(again.hyperpath_hyperarcs, first.hyperpath_hyperarcs);
  // The event stream holds exactly the live structure (what the results database records).
  EXPECT_EQ(run.sink.count(log::Layer::Motion, log::ElementKind::Vertex),
            static_cast<std::int64_t>(run.motion.motionVertices()));
  EXPECT_EQ(run.sink.count(log::Layer::Motion, log::ElementKind::Hyperarc),
            static_cast<std::int64_t>(run.motion.motionHyperarcs()));
  EXPECT_EQ(run.sink.countHyperarcs(log::Layer::Motion, "handover"), handovers);
  (void)arcs;
}

TEST(MotionLayer, ARejectedTransitionConfigurationIsResampledAndTheSamePlanQueriedAgain) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("sorting", {{"robots", "4"}, {"objects", "8"}});
  ASSERT_EQ(run.layer.status, TaskLayerStatus::kFeasible) << run.layer.reason;
  // The region of a motion constraint: the first handover's two configurations.
  int k = 0;
  while (k < static_cast<int>(run.layer.plan.steps.size()) &&
         run.layer.plan.steps[k].action.type != TaskArcType::kHandover)
    ++k;
  ASSERT_LT(k, static_cast<int>(run.layer.plan.steps.size()));
  const TaskArc& a = run.layer.plan.steps[k].action;
  const TransitionConfig before = run.layer.transitions[k];
  ASSERT_TRUE(run.task.rejectTransition(a.robot, before.q));
  ASSERT_TRUE(run.task.rejectTransition(a.robot2, before.q2));
  EXPECT_FALSE(run.task.rejectTransition(a.robot, before.q));  // already known
  const auto after = run.task.resampleTransitions(run.layer.plan, Deadline(120));
  ASSERT_TRUE(after.has_value());
  ASSERT_EQ(after->size(), run.layer.transitions.size());
  const TransitionConfig& now = (*after)[k];
  EXPECT_GT((now.q - before.q).cwiseAbs().maxCoeff() + (now.q2 - before.q2).cwiseAbs().maxCoeff(), 1e-6);
  // The motion query on the same plan with the new configurations.
  const MotionLayerResult motions = run.motion.plan(run.layer.plan, *after, run.task.space(), Deadline(120));
  EXPECT_EQ(motions.status, MotionStatus::kOk) << motions.reason;
}

}  // namespace
}  // namespace dash

namespace dash {
namespace {

using testing::FirstTaskPlan;

// The lab's inspections take their task from pending to done: the motion query walks the whole
// schedule (an inspection as a self-loop would repeat a search state and stop the query there).
TEST(MotionLayer, TheMotionQueryWalksALabScheduleToTheSink) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("lab", {{"containers", "2"}});
  const TaskLayerResult& layer = run.layer;
  ASSERT_EQ(layer.status, TaskLayerStatus::kFeasible) << layer.reason;
  const MotionLayerResult result = run.motion.plan(layer.plan, layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(result.status, MotionStatus::kOk) << result.reason;
  EXPECT_GT(run.sink.countHyperarcs(log::Layer::MotionExtended, "inspect"), 0);
  EXPECT_EQ(run.sink.countHyperarcs(log::Layer::MotionExtended, "sink"), 1);
}

}  // namespace
}  // namespace dash

namespace dash {
namespace {

using testing::FirstTaskPlan;

// Item 2 of issue 36: H_M is built before the motion query, as the paper orders it. Every transition
// hyperarc of the plan (and the anchors they join) is in H_M before the query validates its first move:
// the query's phase starts only after the last of them was added.
TEST(MotionLayer, HMHoldsEveryTransitionOfThePlanBeforeTheMotionQueryStarts) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("sorting", {{"robots", "4"}, {"objects", "8"}});
  ASSERT_EQ(run.layer.status, TaskLayerStatus::kFeasible) << run.layer.reason;
  const std::size_t first_event = run.sink.events().size();
  const MotionLayerResult result = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(result.status, MotionStatus::kOk) << result.reason;
  const std::vector<log::Event> events = run.sink.events();
  std::size_t first_query = events.size(), last_transition = 0, transitions = 0;
  for (std::size_t i = first_event; i < events.size(); ++i) {
    if (const auto* p = std::get_if<log::PhaseEvent>(&events[i].payload))
      if (p->phase == log::Phase::MotionQuery && p->boundary == log::PhaseBoundary::Start)
        first_query = std::min(first_query, i);
    if (const auto* r = std::get_if<log::RepresentationEvent>(&events[i].payload))
      if (r->layer == log::Layer::Motion && r->kind == log::ElementKind::Hyperarc && r->arc_type != "move" &&
          r->arc_type != "sink") {
        last_transition = i;
        ++transitions;
      }
  }
  EXPECT_EQ(transitions, run.layer.plan.steps.size() + 1);  // and the source
  EXPECT_LT(last_transition, first_query);
}

// Item 3 of issue 36: the motion query is a search over H_M, not a walk of the schedule. Deep in a
// shelf cubby the short approach and retreat leave an arm where no move is found; the query then grows
// H_M (farther approach starts and retreat ends along the same axes), takes an alternative, and
// backtracks to the robot's previous visit to take its farther retreat end. H_ME holds the dead
// branches too, so it is larger than the hyperpath found (the schedule length plus the source and sink).
TEST(MotionLayer, TheMotionQueryBacktracksToAFartherRetreatAndHMEHoldsTheBranchesLeft) {
  const OmplSeedScope ompl_seeds(1);
  FirstTaskPlan run("shelf-wall", {{"robots", "2"}, {"objects", "4"}});
  ASSERT_EQ(run.layer.status, TaskLayerStatus::kFeasible) << run.layer.reason;
  const std::size_t arcs_before = run.motion.motionHyperarcs();
  const MotionLayerResult result = run.motion.plan(run.layer.plan, run.layer.transitions, run.task.space(), Deadline(120));
  ASSERT_EQ(result.status, MotionStatus::kOk) << result.reason;
  EXPECT_GT(result.failed_moves, 0u);
  EXPECT_GT(result.backtracks, 0u);
  EXPECT_EQ(run.motion.queryBacktracks(), static_cast<std::int64_t>(result.backtracks));
  EXPECT_EQ(run.motion.extendedHyperarcs(), result.hyperpath_hyperarcs + result.failed_moves + result.backtracks);
  EXPECT_GT(run.motion.extendedHyperarcs(), result.hyperpath_hyperarcs);
  EXPECT_GT(run.motion.motionHyperarcs(), arcs_before);
  // The plan the query returns starts each robot's transit where its previous retreat ended: a
  // backtracked retreat end is the one the next transit leaves from.
  for (const RobotMotionPlan& robot : result.robots)
    for (std::size_t i = 1; i < robot.visits.size(); ++i) {
      ASSERT_FALSE(robot.visits[i].transit.empty());
      EXPECT_LT((robot.visits[i].transit.front() - robot.visits[i - 1].q_post).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((robot.visits[i].transit.back() - robot.visits[i].q_pre).cwiseAbs().maxCoeff(), 1e-12);
    }
}

}  // namespace
}  // namespace dash
