// The task layer on generated scenes with real geometry (UR5e IK, FCL): task conflict detection must
// find what the paper's Algorithm 2 finds there, and the task query must get round it.
#include <gtest/gtest.h>

#include <variant>

#include "engine/events/memory_sink.h"
#include "engine/scenarios/scenario_registry.h"
#include "engine/task/task_layer.h"
#include "engine/task/transition_sampler.h"

namespace dash {
namespace {

struct LayerRun {
  Scene scene;
  log::MemorySink sink;
  TaskLayerResult result;
  std::unique_ptr<CollisionWorld> world;
  std::unique_ptr<CollisionContext> context;
  std::unique_ptr<log::EventEmitter> emitter;
  std::unique_ptr<TaskLayer> layer;

  LayerRun(const std::string& family, std::vector<std::pair<std::string, std::string>> params, std::uint64_t seed,
           const TaskLayerParams& layer_params = {}) {
    scene = generateScenario(family, params, seed, RobotLibrary::loadDefault());
    world = std::make_unique<CollisionWorld>(scene);
    context = std::make_unique<CollisionContext>(*world);
    emitter = std::make_unique<log::EventEmitter>(&sink);
    layer = std::make_unique<TaskLayer>(scene, *world, *context, *emitter, seed, layer_params);
    result = layer->plan(Deadline(120));
  }

  bool visitsExtraLocation() const {
    for (const TaskStep& s : result.plan.steps)
      if (s.action.type == TaskArcType::kPlace &&
          layer->space().location(s.action.object, s.action.location).kind == ObjectLocation::Kind::kExtra)
        return true;
    return false;
  }
};

// Shelf-wall: both cubby slots are goals. A cube already at its goal in the front slot blocks the arm
// that must reach the rear slot behind it, for ever (it will not move again): a history constraint.
// The query then fills every rear slot before the front slot in front of it.
TEST(TaskConflictDetection, FrontGoalBlockingARearGoalGivesAHistoryConstraint) {
  LayerRun run("shelf-wall", {{"robots", "2"}, {"objects", "8"}}, 1);
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  EXPECT_GE(run.sink.countConstraints(log::ConstraintKind::History, log::ConstraintAction::Created), 1);
  bool found = false;
  for (const TaskConstraint& c : run.layer->constraints().all()) {
    if (c.kind != TaskConstraint::Kind::kHistory) continue;
    found = true;
    // v_pre: the blocker at its goal; v_post: the blocked object at its goal (placed there).
    const TaskElement& pre = run.layer->graph().graph().property(c.pre);
    EXPECT_EQ(pre.kind, ElementKind::kObjectAt);
    EXPECT_EQ(pre.location, run.layer->space().goalLocation(pre.object));
    // In the final schedule the blocked placement happens before the blocker reaches its goal.
    const TaskElement& post = run.layer->graph().graph().property(c.post);
    int place_pre = -1, place_post = -1;
    for (int k = 0; k < static_cast<int>(run.result.plan.steps.size()); ++k) {
      const TaskArc& a = run.result.plan.steps[k].action;
      if (a.type != TaskArcType::kPlace) continue;
      if (a.object == pre.object && a.location == pre.location) place_pre = k;
      if (post.kind == ElementKind::kObjectAt && a.object == post.object && a.location == post.location) place_post = k;
    }
    if (place_pre >= 0 && place_post >= 0) {
      EXPECT_LT(place_post, place_pre);
    }
  }
  EXPECT_TRUE(found);
}

// Stocking: every existing item sits at its start, which is also its goal, in front of the slot a new
// item must fill. Frontier constraints alone cannot be met (the item has nowhere else to be), so the
// task space grows an extra stable pose for it, and the schedule moves it out and back.
TEST(TaskConflictDetection, StockingNeedsATaskSpaceExpansion) {
  LayerRun run("stocking", {{"layers", "2"}, {"objects", "4"}}, 1);
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  EXPECT_GE(run.sink.countTaskSpaceExpansions(), 1);
  EXPECT_GE(run.sink.countConstraints(log::ConstraintKind::Frontier, log::ConstraintAction::Created), 1);
  EXPECT_TRUE(run.visitsExtraLocation());
  // Every step of the schedule got its transition configurations.
  ASSERT_EQ(run.result.transitions.size(), run.result.plan.steps.size());
  for (std::size_t k = 0; k < run.result.plan.steps.size(); ++k) {
    const TaskArcType t = run.result.plan.steps[k].action.type;
    if (t == TaskArcType::kPick || t == TaskArcType::kPlace || t == TaskArcType::kHandover) {
      EXPECT_TRUE(run.result.transitions[k].sampled) << "step " << k;
    }
  }
}

// Stocking with three layers: front and middle items of every cubby move out and back in reverse
// order (non-monotone), twelve moved-out items at once in the worst case. The extra poses must leave
// room for each other, else the query drowns in pairwise frontier constraints among them.
TEST(TaskConflictDetection, ThreeLayerStockingIsTaskLevelFeasible) {
  LayerRun run("stocking", {{"layers", "3"}, {"objects", "18"}}, 1);
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  EXPECT_GE(run.sink.countTaskSpaceExpansions(), 12);
  EXPECT_TRUE(run.visitsExtraLocation());
  // Each new item ends at its rear goal: the schedule places every object at its goal last.
  const TaskSpace& space = run.layer->space();
  std::vector<int> last_location(run.scene.objects.size(), -1);
  for (const TaskStep& s : run.result.plan.steps)
    if (s.action.type == TaskArcType::kPlace) last_location[s.action.object] = s.action.location;
  for (int o = 0; o < space.objectCount(); ++o) {
    if (last_location[o] >= 0) {
      EXPECT_EQ(last_location[o], space.goalLocation(o)) << run.scene.objects[o].id;
    }
  }
}

// A motion failure at a handover bans that handover class (robots and grasps) for the next queries,
// whatever the object: the failing configuration is the pair's handover pose, which every cube shares.
TEST(TaskLayerFeedback, MotionFailureAtAHandoverBansItsClass) {
  LayerRun run("sorting", {{"robots", "2"}, {"objects", "2"}}, 1);
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  const TaskStep* handover = nullptr;
  for (const TaskStep& s : run.result.plan.steps)
    if (s.action.type == TaskArcType::kHandover) handover = &s;
  ASSERT_NE(handover, nullptr);
  TaskConstraint c;
  c.kind = TaskConstraint::Kind::kInteraction;
  c.arc = handover->arc;
  c.temporary = true;
  c.from_motion = true;
  c.cause = "test";
  ASSERT_TRUE(run.layer->addConstraint(c));
  const TaskConstraint& added = run.layer->constraints().all().back();
  EXPECT_FALSE(added.arc.valid());
  EXPECT_EQ(added.giver, handover->action.robot);
  EXPECT_EQ(added.receiver, handover->action.robot2);
  EXPECT_TRUE(added.temporary);
  // The next schedule hands no object over that way.
  const TaskLayerResult next = run.layer->plan(Deadline(60));
  if (next.status == TaskLayerStatus::kFeasible) {
    for (const TaskStep& s : next.plan.steps)
      EXPECT_FALSE(s.action.type == TaskArcType::kHandover && s.action.robot == added.giver &&
                   s.action.robot2 == added.receiver && s.action.grasp == added.giver_grasp &&
                   s.action.grasp2 == added.receiver_grasp);
  }
}

// A transition configuration the motion layer found no way to is not chosen again: task conflict
// detection samples another one for the next schedule instead (the region of a motion constraint, which
// the planner logs).
TEST(TaskLayerFeedback, RejectedTransitionConfigurationIsNotChosenAgain) {
  LayerRun run("sorting", {{"robots", "2"}, {"objects", "2"}}, 1);
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  int handover = -1;
  for (int k = 0; k < static_cast<int>(run.result.plan.steps.size()); ++k)
    if (run.result.plan.steps[k].action.type == TaskArcType::kHandover) handover = k;
  ASSERT_GE(handover, 0);
  const int receiver = run.result.plan.steps[handover].action.robot2;
  const JointVector rejected = run.result.transitions[handover].q2;
  ASSERT_TRUE(run.layer->rejectTransition(receiver, rejected));
  EXPECT_FALSE(run.layer->rejectTransition(receiver, rejected));  // known already

  const TaskLayerResult next = run.layer->plan(Deadline(60));
  ASSERT_EQ(next.status, TaskLayerStatus::kFeasible) << next.reason;
  int receiver_configurations = 0;
  for (int k = 0; k < static_cast<int>(next.plan.steps.size()); ++k) {
    const TaskArc& a = next.plan.steps[k].action;
    const TransitionConfig& tc = next.transitions[k];
    if (a.robot == receiver) {
      EXPECT_GT((tc.q - rejected).cwiseAbs().maxCoeff(), 1e-6) << "step " << k;
    }
    if (a.type == TaskArcType::kHandover && a.robot2 == receiver) {
      ++receiver_configurations;
      EXPECT_GT((tc.q2 - rejected).cwiseAbs().maxCoeff(), 1e-6) << "step " << k;
    }
  }
  EXPECT_GT(receiver_configurations, 0);  // the same handover, with another configuration
}

// Interaction constraints that leave an object no route to its goal end the task layer without task
// space expansions: another object's move-out state gives it no route. (Before, every object of the
// frontier constraints was expanded, over and over, while the query spent its whole budget each time.)
TEST(TaskLayerFeedback, ObjectWithoutARouteGetsNoExpansions) {
  LayerRun run("sorting", {{"robots", "2"}, {"objects", "2"}}, 1);
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  const TaskSpace& space = run.layer->space();
  // An object that blocks the other's goal: the kind of constraint that asks for expansions.
  const auto blocker = run.layer->graph().find(TaskElement::objectAt(1, space.startLocation(1)));
  const auto blocked = run.layer->graph().find(TaskElement::objectAt(0, space.goalLocation(0)));
  ASSERT_TRUE(blocker && blocked);
  ASSERT_TRUE(run.layer->addConstraint({TaskConstraint::Kind::kFrontier, *blocker, *blocked}));
  // No handover at all between the two arms.
  for (int giver = 0; giver < 2; ++giver)
    for (GraspClass g1 : {GraspClass::kTop, GraspClass::kSide, GraspClass::kBottom})
      for (GraspClass g2 : {GraspClass::kTop, GraspClass::kSide, GraspClass::kBottom}) {
        TaskConstraint c;
        c.kind = TaskConstraint::Kind::kInteraction;
        c.giver = giver;
        c.receiver = 1 - giver;
        c.giver_grasp = g1;
        c.receiver_grasp = g2;
        run.layer->addConstraint(c);
      }
  const auto expansions = run.sink.countTaskSpaceExpansions();
  const TaskLayerResult next = run.layer->plan(Deadline(60));
  EXPECT_EQ(next.status, TaskLayerStatus::kInfeasible);
  EXPECT_NE(next.reason.find("has no route to its goal"), std::string::npos) << next.reason;
  EXPECT_FALSE(next.no_route_in_task_hypergraph);  // the interaction constraints cut the route, not H_T
  EXPECT_EQ(run.sink.countTaskSpaceExpansions(), expansions);
  // A restart (Lazy-DaSH when nothing is left to try) lifts every constraint: the plan is back.
  run.layer->restart("test");
  EXPECT_EQ(run.layer->restarts(), 1);
  EXPECT_TRUE(run.layer->constraints().empty());
  const TaskLayerResult again = run.layer->plan(Deadline(60));
  EXPECT_EQ(again.status, TaskLayerStatus::kFeasible) << again.reason;
}

// Into and out of a cubby the gripper moves along its approach axis: the configurations chosen for
// picks and places there are on IK branches that can back straight out.
TEST(TransitionSampling, CubbyGraspsCanBackStraightOut) {
  const Scene scene = generateScenario("stocking", {{"layers", "3"}, {"objects", "6"}}, 1, RobotLibrary::loadDefault());
  const CollisionWorld world(scene);
  CollisionContext context(world);
  TransitionSampler sampler(world, context);
  int checked = 0;
  for (int o = 0; o < static_cast<int>(scene.objects.size()); ++o) {
    const Pose& goal = *scene.objects[o].X_WO_goal;
    for (const GraspConfig& gc : sampler.graspConfigs(0, o, goal, GraspClass::kSide, 6, true)) {
      EXPECT_TRUE(sampler.approachLineFree(0, gc.q, HeldObject{o, gc.X_TO}, 0.2)) << scene.objects[o].id;
      for (const JointVector& q : sampler.holdConfigs(0, o, goal, gc.X_TO, 1, true)) {
        EXPECT_TRUE(sampler.approachLineFree(0, q, HeldObject{o, gc.X_TO}, 0.2)) << scene.objects[o].id;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 0);
}

// Grasp and hold configurations depend on the static scene only: asked again (as task conflict
// detection does after every constraint), the sampler answers from memory, without a collision check,
// and the answer for another pose is its own.
TEST(TransitionSampler, RemembersStaticAnswers) {
  const Scene scene = generateScenario("shelf-wall", {{"robots", "2"}, {"objects", "4"}}, 1, RobotLibrary::loadDefault());
  const CollisionWorld world(scene);
  CollisionContext context(world);
  TransitionSampler sampler(world, context);
  const Pose& goal = *scene.objects[0].X_WO_goal;
  const std::vector<GraspConfig> first = sampler.graspConfigs(0, 0, goal, GraspClass::kSide, 6, true);
  ASSERT_FALSE(first.empty());
  const std::vector<JointVector> holds = sampler.holdConfigs(0, 0, goal, first[0].X_TO, 2, true);
  const std::uint64_t checks = context.counters().configuration_checks;
  const std::vector<GraspConfig> again = sampler.graspConfigs(0, 0, goal, GraspClass::kSide, 6, true);
  EXPECT_EQ(sampler.holdConfigs(0, 0, goal, first[0].X_TO, 2, true).size(), holds.size());
  EXPECT_EQ(context.counters().configuration_checks, checks);
  ASSERT_EQ(again.size(), first.size());
  for (std::size_t i = 0; i < first.size(); ++i) EXPECT_EQ(again[i].q, first[i].q);
  // Moved 5 cm along x: other configurations (the translation is part of what is remembered).
  const Pose moved = makePose(Vec3(0.05, 0, 0)) * goal;
  const std::vector<GraspConfig> elsewhere = sampler.graspConfigs(0, 0, moved, GraspClass::kSide, 6, true);
  EXPECT_GT(context.counters().configuration_checks, checks);
  if (!elsewhere.empty()) {
    EXPECT_NE(elsewhere[0].q, first[0].q);
  }
}

// Seed 2: no single grasp serves an item's pick from its move-out pose and its place back at its
// goal. That combination is banned for some task queries, never the goal placement for ever (which
// left the item no way home: infeasible).
LayerRun& threeLayerStockingSeed2() {
  static LayerRun run("stocking", {{"layers", "3"}, {"objects", "18"}}, 2);
  return run;
}

TEST(TaskConflictDetection, GraspChainFailureDoesNotForbidAGoalForEver) {
  LayerRun& run = threeLayerStockingSeed2();
  ASSERT_EQ(run.result.status, TaskLayerStatus::kFeasible) << run.result.reason;
  for (const TaskConstraint& c : run.layer->constraints().all()) {
    if (c.kind == TaskConstraint::Kind::kInteraction && c.arc.valid() && !c.temporary) {
      EXPECT_EQ(c.cause.find("@start=goal"), std::string::npos) << c.cause;
    }
  }
}

// Seed 2 again: an item's move-out pose where no grasp serves its pick from the start and its place
// there. The pose is resampled (paper: "resampling is performed to search for valid alternatives")
// before its step is banned when move_out_resamples allows it; with none (the default and the paper
// value) the step is banned at once.
TEST(TaskConflictDetection, AMoveOutPoseWithNoTransitionConfigurationIsResampledBeforeItsStepIsBanned) {
  TaskLayerParams three;
  three.conflicts.chain_location_resamples = 3;
  LayerRun resampling("stocking", {{"layers", "3"}, {"objects", "18"}}, 2, three);
  ASSERT_EQ(resampling.result.status, TaskLayerStatus::kFeasible) << resampling.result.reason;
  EXPECT_GE(resampling.sink.counter("move_out_resamples"), 1);
  LayerRun& banning = threeLayerStockingSeed2();  // the default: move_out_resamples 0
  ASSERT_EQ(banning.result.status, TaskLayerStatus::kFeasible) << banning.result.reason;
  EXPECT_EQ(banning.sink.counter("move_out_resamples"), 0);
}

// Created constraints that ban a place at a move-out pose for want of any transition configuration
// there: a move-out pose no grasp chain can use.
std::int64_t unusableMoveOutBans(const LayerRun& run) {
  std::int64_t n = 0;
  for (const log::Event& e : run.sink.events()) {
    const auto* c = std::get_if<log::ConstraintEvent>(&e.payload);
    if (c && c->action == log::ConstraintAction::Created && c->conflict.find("@extra") != std::string::npos &&
        c->conflict.find("no collision-free transition configuration") != std::string::npos)
      ++n;
  }
  return n;
}

// Seed 2 again: items taken out of a shelf cubby with a side grasp. A move-out pose on the low table
// that only some other grasp reaches cannot serve their chain (pick with the side grasp, place there),
// and its place step is banned for want of a transition configuration. With move_out_one_grasp (off by
// default and in the paper) task space expansion looks first for poses that trap no robot
// (MoveOutSampler): fewer such bans than with it off.
TEST(TaskSpaceExpansion, MoveOutPosesThatTrapNoRobotAreBannedLessOftenOnThreeLayerStocking) {
  TaskLayerParams one_grasp;
  one_grasp.move_out_one_grasp = true;
  LayerRun on("stocking", {{"layers", "3"}, {"objects", "18"}}, 2, one_grasp);
  LayerRun& off = threeLayerStockingSeed2();  // the default
  ASSERT_EQ(on.result.status, TaskLayerStatus::kFeasible) << on.result.reason;
  EXPECT_GE(unusableMoveOutBans(off), 1);
  EXPECT_LT(unusableMoveOutBans(on), unusableMoveOutBans(off));
}

}  // namespace
}  // namespace dash
