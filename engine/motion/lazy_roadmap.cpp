#include "engine/motion/lazy_roadmap.h"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/prm/LazyPRM.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <algorithm>
#include <cmath>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/core/stopwatch.h"
#include "engine/motion/ompl_validity.h"
#include "engine/motion/seeded_ompl.h"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace dash {

namespace {
constexpr double kSameState = 1e-6;  // radians (metres for the gantry), largest joint difference
}  // namespace

// Validity of states and straight motions for one robot in the current MotionContext.
struct LazyRoadmap::Checker {
  const CollisionWorld* world;
  CollisionContext* context;
  int robot;
  int dof;
  MotionContext motion;
  mutable double check_seconds = 0.0;  ///< spent in the two validity functions (lazy validation)

  bool stateValid(const JointVector& q) const {
    const RobotState self{robot, q, motion.held};
    if (motion.parked.empty()) return !robotInCollision(*world, *context, self, motion.layout);
    std::vector<RobotState> states{self};
    states.insert(states.end(), motion.parked.begin(), motion.parked.end());
    return !robotsInCollision(*world, *context, states, motion.layout);
  }
  bool motionValid(const JointVector& a, const JointVector& b) const {
    if (motion.parked.empty())
      return !segmentInCollision(*world, *context, RobotState{robot, a, motion.held}, b, motion.layout);
    std::vector<RobotMotion> motions{{RobotState{robot, a, motion.held}, b}};
    for (const RobotState& p : motion.parked) motions.push_back({p, p.q});
    return !motionsInCollision(*world, *context, motions, motion.layout);
  }
};

std::size_t querySampleBudget(const RoadmapParams& params, std::size_t vertices) {
  if (vertices >= params.max_vertices) return 1;  // the one sample Lazy-PRM draws before it searches
  if (vertices >= params.dense_vertices) return std::min(params.query_samples, params.dense_query_samples);
  return params.query_samples;
}

LazyRoadmap::LazyRoadmap(const CollisionWorld& world, CollisionContext& context, int robot, RoadmapParams params)
    : world_(&world), context_(&context), robot_(robot), params_(params) {
  const RobotModel& model = *world.scene().robots[robot].model;
  const int dof = model.dof();
  checker_ = std::make_shared<Checker>(Checker{&world, &context, robot, dof, {}});
  si_ = std::make_shared<ob::SpaceInformation>(jointSpace(model));
  const Checker* c = checker_.get();
  installValidity(
      si_,
      [c](const ob::State* s) {
        const Stopwatch watch;
        const bool valid = c->stateValid(jointsOf(s, c->dof));
        c->check_seconds += watch.seconds();
        return valid;
      },
      [c](const ob::State* a, const ob::State* b) {
        const Stopwatch watch;
        const bool valid = c->motionValid(jointsOf(a, c->dof), jointsOf(b, c->dof));
        c->check_seconds += watch.seconds();
        return valid;
      });
  si_->setup();
  planner_ = std::make_shared<og::LazyPRM>(si_, false);
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
    planner_->clearValidity();
    last_context_ = motion;
  }
  // An invalid end is answered at once: given one, OMPL keeps resampling the goal (sleeping between
  // tries) until the termination condition, which is the whole budget.
  return checker_->stateValid(q_start) && checker_->stateValid(q_goal);
}

std::optional<std::vector<JointVector>> LazyRoadmap::solve(ob::Planner& planner, const JointVector& q_start,
                                                           const JointVector& q_goal, std::size_t work,
                                                           const Deadline& deadline) {
  auto pdef = std::make_shared<ob::ProblemDefinition>(si_);
  ob::ScopedState<> start(si_), goal(si_);
  setJoints(q_start, start.get());
  setJoints(q_goal, goal.get());
  pdef->setStartAndGoalStates(start, goal);
  planner.setProblemDefinition(pdef);
  const double budget = std::min(params_.query_seconds, std::max(0.0, deadline.secondsLeft()));
  // Lazy-PRM evaluates the condition once per sample it draws, RRT-Connect once per iteration.
  std::size_t evaluations = 0;
  const ob::PlannerTerminationCondition ptc(
      [&, end = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget)] {
        return ++evaluations > work || deadline.expired() || std::chrono::steady_clock::now() >= end;
      });
  // Phases (paper, "Planning Time"): the planner's own work (sampling, neighbours, graph search, the
  // trees of global sampling) is roadmap construction and growth, booked as motion construction; its
  // lazy collision checks stay with the phase that asked (motion query or conflict resolution).
  const Stopwatch watch;
  const double checks_before = checker_->check_seconds;
  const ob::PlannerStatus status = planner.solve(ptc);
  if (emitter_ != nullptr)
    emitter_->rebook(log::Phase::MotionConstruction, watch.seconds() - (checker_->check_seconds - checks_before));
  if (status != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  auto path = std::static_pointer_cast<og::PathGeometric>(pdef->getSolutionPath());
  if (params_.simplify) {
    SeededPathSimplifier simplifier(si_);
    simplifier.reduceVertices(*path);
    simplifier.shortcutPath(*path);
  }
  // The end points are exactly the requested configurations (OMPL copies them). States closer than
  // kSameState to the one before are left out: RRT-Connect may join its trees at nearly the same state,
  // and a timed path cannot spend no time on a move.
  std::vector<JointVector> out{q_start};
  for (std::size_t i = 1; i + 1 < path->getStateCount(); ++i) {
    JointVector q = jointsOf(path->getState(i), checker_->dof);
    if ((q - out.back()).cwiseAbs().maxCoeff() >= kSameState) out.push_back(std::move(q));
  }
  if (out.size() > 1 && (q_goal - out.back()).cwiseAbs().maxCoeff() < kSameState) out.pop_back();
  out.push_back(q_goal);
  return out;
}

std::optional<std::vector<JointVector>> LazyRoadmap::query(const JointVector& q_start, const JointVector& q_goal,
                                                           const MotionContext& motion, const Deadline& deadline) {
  if (!prepare(q_start, q_goal, motion)) return std::nullopt;
  planner_->clearQuery();
  return solve(*planner_, q_start, q_goal, querySampleBudget(params_, vertexCount()), deadline);
}

std::optional<std::vector<JointVector>> LazyRoadmap::queryTrees(const JointVector& q_start, const JointVector& q_goal,
                                                                const MotionContext& motion, const Deadline& deadline) {
  if (!prepare(q_start, q_goal, motion)) return std::nullopt;
  SeededRRTConnect trees(si_);
  trees.setRange(planner_->getRange());
  trees.setup();
  return solve(trees, q_start, q_goal, params_.tree_iterations, deadline);
}

void LazyRoadmap::scaleBudget(double factor) {
  params_.scale(factor);
}

std::size_t LazyRoadmap::vertexCount() const { return planner_->milestoneCount(); }
std::size_t LazyRoadmap::edgeCount() const { return planner_->edgeCount(); }

}  // namespace dash
