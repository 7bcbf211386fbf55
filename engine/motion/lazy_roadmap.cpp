#include "engine/motion/lazy_roadmap.h"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <algorithm>
#include <chrono>
#include <cmath>

#include "engine/collision/collision_queries.h"
#include "engine/collision/region_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/core/stopwatch.h"
#include "engine/motion/context_lazy_prm.h"
#include "engine/motion/ompl_validity.h"
#include "engine/motion/seeded_ompl_planners.h"
#include "engine/motion/static_robot_validity.h"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace dash {

namespace {
constexpr double kSameState = 1e-6;  // radians (metres for the gantry), largest joint difference
}  // namespace

// Validity of states and straight motions for one robot: statically (with an empty hand, against what
// never moves: the roadmap's own validity) and in the current MotionContext (everything).
struct LazyRoadmap::Checker {
  const CollisionWorld* world;
  CollisionContext* context;
  int robot;
  int dof;
  StaticRobotValidity statically;
  MotionContext motion;
  mutable double check_seconds = 0.0;  ///< spent in the validity functions (lazy validation)

  bool stateValid(const JointVector& q) const {
    const RobotState self{robot, q, motion.held};
    if (robotEntersRegions(*world, *context, self, motion.avoid)) return false;
    if (motion.parked.empty()) return !robotInCollision(*world, *context, self, motion.layout);
    return !robotsAmongParked(*world, *context, std::span<const RobotState>(&self, 1), motion.parked, motion.layout);
  }
  bool motionValid(const JointVector& a, const JointVector& b) const {
    if (segmentEntersRegions(*world, *context, RobotState{robot, a, motion.held}, b, motion.avoid)) return false;
    if (motion.parked.empty())
      return !segmentInCollision(*world, *context, RobotState{robot, a, motion.held}, b, motion.layout);
    const RobotMotion self{RobotState{robot, a, motion.held}, b};
    return !motionsAmongParked(*world, *context, std::span<const RobotMotion>(&self, 1), motion.parked, motion.layout);
  }
  /// `valid` timed into check_seconds.
  template <class Check>
  bool timed(Check&& valid) const {
    const Stopwatch watch;
    const bool ok = valid();
    check_seconds += watch.seconds();
    return ok;
  }
};

std::size_t querySampleBudget(const RoadmapParams& params, std::size_t vertices) {
  if (vertices >= params.max_vertices) return 0;
  if (vertices >= params.dense_vertices) return std::min(params.query_samples, params.dense_query_samples);
  return params.query_samples;
}

LazyRoadmap::LazyRoadmap(const CollisionWorld& world, CollisionContext& context, int robot, RoadmapParams params)
    : world_(&world), context_(&context), robot_(robot), params_(params) {
  const RobotModel& model = *world.scene().robots[robot].model;
  const int dof = model.dof();
  checker_ = std::make_shared<Checker>(Checker{&world, &context, robot, dof, {world, context, robot}, {}});
  const Checker* c = checker_.get();
  const auto space = jointSpace(model);
  static_si_ = std::make_shared<ob::SpaceInformation>(space);
  installValidity(
      static_si_,
      [c](const ob::State* s) { return c->timed([&] { return c->statically.stateValid(jointsOf(s, c->dof)); }); },
      [c](const ob::State* a, const ob::State* b) {
        return c->timed([&] { return c->statically.motionValid(jointsOf(a, c->dof), jointsOf(b, c->dof)); });
      });
  static_si_->setup();
  si_ = std::make_shared<ob::SpaceInformation>(space);
  installValidity(
      si_, [c](const ob::State* s) { return c->timed([&] { return c->stateValid(jointsOf(s, c->dof)); }); },
      [c](const ob::State* a, const ob::State* b) {
        return c->timed([&] { return c->motionValid(jointsOf(a, c->dof), jointsOf(b, c->dof)); });
      });
  si_->setup();
  planner_ = std::make_shared<ContextLazyPRM>(static_si_);
  const double range = model.kinematics == KinematicsKind::kUrDh ? params_.max_edge_length : 0.3;
  planner_->setRange(range);
  planner_->setMaxNearestNeighbors(params_.neighbours);
  planner_->setup();
}

LazyRoadmap::~LazyRoadmap() = default;

bool LazyRoadmap::prepare(const JointVector& q_start, const JointVector& q_goal, const MotionContext& motion) {
  if (!last_context_ || !last_context_->sameAs(motion)) {
    checker_->motion = motion;
    // Roadmap paths run between approach lines: a held object keeps the clearance on every face.
    checker_->motion.held = inTransit(motion.held);
    planner_->forgetContext();
    last_context_ = motion;
  }
  // An invalid end is answered at once: no path can start or end there.
  return checker_->stateValid(q_start) && checker_->stateValid(q_goal);
}

std::vector<JointVector> LazyRoadmap::finish(og::PathGeometric& path, const JointVector& q_start,
                                             const JointVector& q_goal) const {
  if (params_.simplify) {
    SeededPathSimplifier simplifier(si_);
    simplifier.reduceVertices(path, params_.simplify_steps, params_.simplify_empty_steps);
    simplifier.shortcutPath(path);
  }
  // The end points are exactly the requested configurations (OMPL copies them). States closer than
  // kSameState to the one before are left out: RRT-Connect may join its trees at nearly the same state,
  // and a timed path cannot spend no time on a move.
  std::vector<JointVector> out{q_start};
  for (std::size_t i = 1; i + 1 < path.getStateCount(); ++i) {
    JointVector q = jointsOf(path.getState(i), checker_->dof);
    if ((q - out.back()).cwiseAbs().maxCoeff() >= kSameState) out.push_back(std::move(q));
  }
  if (out.size() > 1 && (q_goal - out.back()).cwiseAbs().maxCoeff() < kSameState) out.pop_back();
  out.push_back(q_goal);
  return out;
}

// Phases (docs/planners.md "Phases", one accounting for both planners): inside the motion query, the
// planner's own work (sampling, neighbours, graph search, the trees of global sampling) is roadmap
// construction and growth, booked as motion construction, and its lazy collision checks stay with the
// motion query. A roadmap query asked by conflict resolution (a replan around robots in the way) is
// booked as conflict resolution whole, as DaSH's replans are.
void LazyRoadmap::bookConstruction(double seconds, double check_seconds_before) {
  if (emitter_ != nullptr && emitter_->inPhase(log::Phase::MotionQuery))
    emitter_->rebook(log::Phase::MotionConstruction, seconds - (checker_->check_seconds - check_seconds_before));
}

std::optional<std::vector<JointVector>> LazyRoadmap::query(const JointVector& q_start, const JointVector& q_goal,
                                                           const MotionContext& motion, const Deadline& deadline) {
  if (!prepare(q_start, q_goal, motion)) return std::nullopt;
  ob::ScopedState<> start(si_), goal(si_);
  setJoints(q_start, start.get());
  setJoints(q_goal, goal.get());
  const double budget = std::min(params_.query_seconds, std::max(0.0, deadline.secondsLeft()));
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget);
  const Checker* c = checker_.get();
  const Stopwatch watch;
  const double checks_before = checker_->check_seconds;
  const auto states = planner_->solveInContext(
      start.get(), goal.get(), querySampleBudget(params_, vertexCount()),
      [&] { return deadline.expired() || std::chrono::steady_clock::now() >= end; },
      [c](const ob::State* s) { return c->timed([&] { return c->stateValid(jointsOf(s, c->dof)); }); },
      [c](const ob::State* a, const ob::State* b) {
        return c->timed([&] { return c->motionValid(jointsOf(a, c->dof), jointsOf(b, c->dof)); });
      });
  bookConstruction(watch.seconds(), checks_before);
  if (!states) return std::nullopt;
  og::PathGeometric path(si_);
  for (const ob::State* s : *states) path.append(s);
  return finish(path, q_start, q_goal);
}

std::optional<std::vector<JointVector>> LazyRoadmap::queryTrees(const JointVector& q_start, const JointVector& q_goal,
                                                                const MotionContext& motion, const Deadline& deadline) {
  if (!prepare(q_start, q_goal, motion)) return std::nullopt;
  SeededRRTConnect trees(si_);
  trees.setRange(planner_->getRange());
  trees.setup();
  auto pdef = std::make_shared<ob::ProblemDefinition>(si_);
  ob::ScopedState<> start(si_), goal(si_);
  setJoints(q_start, start.get());
  setJoints(q_goal, goal.get());
  pdef->setStartAndGoalStates(start, goal);
  trees.setProblemDefinition(pdef);
  const double budget = std::min(params_.query_seconds, std::max(0.0, deadline.secondsLeft()));
  // RRT-Connect evaluates the condition once per iteration: its work budget.
  std::size_t iterations = 0;
  const ob::PlannerTerminationCondition ptc(
      [&, end = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget)] {
        return ++iterations > params_.tree_iterations || deadline.expired() || std::chrono::steady_clock::now() >= end;
      });
  const Stopwatch watch;
  const double checks_before = checker_->check_seconds;
  const ob::PlannerStatus status = trees.solve(ptc);
  bookConstruction(watch.seconds(), checks_before);
  if (status != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  auto& path = *std::static_pointer_cast<og::PathGeometric>(pdef->getSolutionPath());
  if (params_.keep_tree_paths) {
    std::vector<const ob::State*> states;
    for (std::size_t i = 0; i < path.getStateCount(); ++i) states.push_back(path.getState(i));
    planner_->addPath(states);
  }
  return finish(path, q_start, q_goal);
}

void LazyRoadmap::scaleBudget(double factor) {
  params_.scale(factor);
}

std::size_t LazyRoadmap::vertexCount() const { return planner_->milestoneCount(); }
std::size_t LazyRoadmap::edgeCount() const { return planner_->edgeCount(); }

}  // namespace dash
