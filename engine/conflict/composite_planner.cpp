#include "engine/conflict/composite_planner.h"

#include <ompl/base/ProblemDefinition.h>
#include <ompl/base/SpaceInformation.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/geometric/PathGeometric.h>
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <algorithm>
#include <chrono>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/core/check.h"
#include "engine/motion/ompl_validity.h"
#include "engine/motion/seeded_ompl_planners.h"

namespace ob = ompl::base;
namespace og = ompl::geometric;

namespace dash {

namespace {

constexpr double kPi = 3.141592653589793;

/// The stacked space: mover i's joints at offsets[i] .. offsets[i] + dof_i.
struct Stacking {
  std::vector<int> offsets;
  std::vector<int> dofs;
  int total = 0;

  std::vector<JointVector> split(const ob::State* s) const {
    const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    std::vector<JointVector> out;
    for (std::size_t i = 0; i < dofs.size(); ++i) {
      JointVector q(dofs[i]);
      for (int j = 0; j < dofs[i]; ++j) q[j] = v->values[offsets[i] + j];
      out.push_back(q);
    }
    return out;
  }
  void join(const std::vector<JointVector>& qs, ob::State* s) const {
    auto* v = s->as<ob::RealVectorStateSpace::StateType>();
    for (std::size_t i = 0; i < dofs.size(); ++i)
      for (int j = 0; j < dofs[i]; ++j) v->values[offsets[i] + j] = qs[i][j];
  }
};

struct CompositeChecker {
  const CollisionWorld* world;
  CollisionContext* context;
  const CompositeProblem* problem;
  Stacking stacking;

  std::vector<RobotState> states(const std::vector<JointVector>& qs) const {
    std::vector<RobotState> out;
    for (std::size_t i = 0; i < qs.size(); ++i) out.push_back({problem->robots[i], qs[i], problem->held[i]});
    return out;
  }
  bool stateValid(const ob::State* s) const {
    return !robotsAmongParked(*world, *context, states(stacking.split(s)), problem->parked, problem->layout);
  }
  bool motionValid(const ob::State* a, const ob::State* b) const {
    const std::vector<JointVector> qa = stacking.split(a), qb = stacking.split(b);
    std::vector<RobotMotion> motions;
    for (std::size_t i = 0; i < qa.size(); ++i) motions.push_back({{problem->robots[i], qa[i], problem->held[i]}, qb[i]});
    // Finer than the schedule checker, which samples the same motion at other instants (its time is
    // cut wherever any robot's timeline bends): a graze one sampling misses, the other may find.
    return !motionsAmongParked(*world, *context, motions, problem->parked, problem->layout, nullptr,
                               {CheckScope::kAll, true, kSegmentResolution / 2});
  }
};

}  // namespace

std::optional<CompositePath> planComposite(const CollisionWorld& world, CollisionContext& context,
                                           const CompositeProblem& problem, const CompositeParams& params,
                                           const Deadline& deadline) {
  const std::size_t n = problem.robots.size();
  DASH_DEMAND(n > 0 && problem.start.size() == n && problem.goal.size() == n && problem.held.size() == n);
  CompositeChecker checker{&world, &context, &problem, {}};
  for (int r : problem.robots) {
    checker.stacking.offsets.push_back(checker.stacking.total);
    const int dof = world.scene().robots[r].model->dof();
    checker.stacking.dofs.push_back(dof);
    checker.stacking.total += dof;
  }
  auto space = std::make_shared<ob::RealVectorStateSpace>(checker.stacking.total);
  ob::RealVectorBounds bounds(checker.stacking.total);
  for (std::size_t i = 0; i < n; ++i) {
    const RobotModel& model = *world.scene().robots[problem.robots[i]].model;
    const bool revolute = model.kinematics == KinematicsKind::kUrDh;
    for (int j = 0; j < checker.stacking.dofs[i]; ++j) {
      const int k = checker.stacking.offsets[i] + j;
      // The start and goal may lie outside [-pi, pi] (a wrist turned further): keep them inside.
      double lo = revolute ? std::max(model.limits.position_min[j], -kPi) : model.limits.position_min[j];
      double hi = revolute ? std::min(model.limits.position_max[j], kPi) : model.limits.position_max[j];
      lo = std::min({lo, problem.start[i][j], problem.goal[i][j]});
      hi = std::max({hi, problem.start[i][j], problem.goal[i][j]});
      bounds.setLow(k, lo);
      bounds.setHigh(k, hi);
    }
  }
  space->setBounds(bounds);
  seedStateSamplers(*space);
  auto si = std::make_shared<ob::SpaceInformation>(space);
  installValidity(
      si, [&checker](const ob::State* s) { return checker.stateValid(s); },
      [&checker](const ob::State* a, const ob::State* b) { return checker.motionValid(a, b); });
  si->setup();

  ob::ScopedState<> start(si), goal(si);
  checker.stacking.join(problem.start, start.get());
  checker.stacking.join(problem.goal, goal.get());
  if (!checker.stateValid(start.get()) || !checker.stateValid(goal.get())) return std::nullopt;
  // Straight there first: often the movers only need each other's synchronised timing.
  if (checker.motionValid(start.get(), goal.get())) return CompositePath{problem.start, problem.goal};

  auto pdef = std::make_shared<ob::ProblemDefinition>(si);
  pdef->setStartAndGoalStates(start, goal);
  auto planner = std::make_shared<SeededRRTConnect>(si);
  planner->setRange(params.range);
  planner->setProblemDefinition(pdef);
  planner->setup();
  const double budget = std::min(params.seconds, std::max(0.0, deadline.secondsLeft()));
  // RRTConnect::solve evaluates the condition once per iteration (a fixed goal state is never resampled).
  std::size_t evaluations = 0;
  const ob::PlannerTerminationCondition ptc(
      [&, end = std::chrono::steady_clock::now() + std::chrono::duration<double>(budget)] {
        return ++evaluations > params.iterations || deadline.expired() || std::chrono::steady_clock::now() >= end;
      });
  if (planner->solve(ptc) != ob::PlannerStatus::EXACT_SOLUTION) return std::nullopt;
  auto path = std::static_pointer_cast<og::PathGeometric>(pdef->getSolutionPath());
  if (params.simplify) {
    SeededPathSimplifier simplifier(si);
    simplifier.reduceVertices(*path);
    simplifier.shortcutPath(*path);
  }
  CompositePath out;
  for (std::size_t i = 0; i < path->getStateCount(); ++i) out.push_back(checker.stacking.split(path->getState(i)));
  out.front() = problem.start;  // exactly the requested configurations (OMPL copies them)
  out.back() = problem.goal;
  return out;
}

}  // namespace dash
