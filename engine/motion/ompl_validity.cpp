#include "engine/motion/ompl_validity.h"

#include <ompl/base/MotionValidator.h>
#include <ompl/base/StateValidityChecker.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>

#include <utility>

namespace ob = ompl::base;

namespace dash {

namespace {

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

}  // namespace dash
