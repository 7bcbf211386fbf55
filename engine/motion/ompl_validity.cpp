#include "engine/motion/ompl_validity.h"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <algorithm>
#include <utility>

#include "engine/motion/seeded_ompl.h"

namespace ob = ompl::base;

namespace dash {

namespace {

constexpr double kPi = 3.141592653589793;

class PredicateStateChecker final : public ob::StateValidityChecker {
 public:
  PredicateStateChecker(const ob::SpaceInformationPtr& si, StatePredicate valid)
      : ob::StateValidityChecker(si), valid_(std::move(valid)) {}
  bool isValid(const ob::State* s) const override { return valid_(s); }

 private:
  StatePredicate valid_;
};

class PredicateMotionValidator final : public ob::MotionValidator {
 public:
  PredicateMotionValidator(const ob::SpaceInformationPtr& si, MotionPredicate predicate)
      : ob::MotionValidator(si), predicate_(std::move(predicate)) {}
  bool checkMotion(const ob::State* s1, const ob::State* s2) const override {
    const bool ok = predicate_(s1, s2);
    ok ? ++valid_ : ++invalid_;  // OMPL's own counters
    return ok;
  }
  bool checkMotion(const ob::State* s1, const ob::State* s2, std::pair<ob::State*, double>& last) const override {
    if (checkMotion(s1, s2)) return true;
    if (last.first != nullptr) si_->copyState(last.first, s1);
    last.second = 0.0;
    return false;
  }

 private:
  MotionPredicate predicate_;
};

}  // namespace

JointVector jointsOf(const ob::State* s, int dof) {
  const auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  JointVector q(dof);
  for (int i = 0; i < dof; ++i) q[i] = v->values[i];
  return q;
}

void setJoints(const JointVector& q, ob::State* s) {
  auto* v = s->as<ob::RealVectorStateSpace::StateType>();
  for (int i = 0; i < q.size(); ++i) v->values[i] = q[i];
}

void installValidity(const ob::SpaceInformationPtr& si, StatePredicate state_valid, MotionPredicate motion_valid) {
  si->setStateValidityChecker(std::make_shared<PredicateStateChecker>(si, std::move(state_valid)));
  si->setMotionValidator(std::make_shared<PredicateMotionValidator>(si, std::move(motion_valid)));
}

std::shared_ptr<ompl::base::RealVectorStateSpace> jointSpace(const RobotModel& model) {
  const int dof = model.dof();
  auto space = std::make_shared<ompl::base::RealVectorStateSpace>(dof);
  ompl::base::RealVectorBounds bounds(dof);
  const bool revolute = model.kinematics == KinematicsKind::kUrDh;
  for (int i = 0; i < dof; ++i) {
    bounds.setLow(i, revolute ? std::max(model.limits.position_min[i], -kPi) : model.limits.position_min[i]);
    bounds.setHigh(i, revolute ? std::min(model.limits.position_max[i], kPi) : model.limits.position_max[i]);
  }
  space->setBounds(bounds);
  seedStateSamplers(*space);
  return space;
}

}  // namespace dash
