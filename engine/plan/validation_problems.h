#pragma once
// Internal to the plan validator: turning what the certified geometric check found into problems
// (one per pair and stretch of time), and the per-pair clearances of the report.
#include <vector>

#include "engine/collision/collision_world.h"
#include "engine/plan/certified_stretch.h"
#include "engine/plan/plan_validator.h"
#include "engine/plan/validation_timeline.h"

namespace dash::validation {

/// One instant at which the two holders of an object put it at different places.
struct HandoverMismatch {
  int object = -1;
  int robot = -1;
  int robot2 = -1;
  int epoch = 0;
  double t = 0.0;
  double distance = 0.0;  ///< how far the two attachments disagree
};

/// Which problem a colliding pair is.
ProblemKind collisionKind(const CollisionElement& a, const CollisionElement& b);

/// Resting objects only move at events: each epoch's layout is checked once (contact boxes).
std::vector<ValidationProblem> restingObjectProblems(const CollisionWorld& world, const Timeline& timeline);

/// Stretches of the same robot (body, for self collisions) and the same other party closer than
/// `join` in time become one problem, with the smallest distance of them all.
void appendContactProblems(const Scene& scene, const ValidationOptions& options, std::vector<PairContact> contacts,
                           double join, std::vector<ValidationProblem>& problems);

/// One problem per object and epoch with two holders that disagree.
void appendHandoverProblems(const Scene& scene, const ValidationOptions& options,
                            std::vector<HandoverMismatch> mismatches, std::vector<ValidationProblem>& problems);

/// report.closest and report.pairs from the pairs' minima.
void fillClearances(const Scene& scene, const PairMinima& minima, ValidationReport& report);

}  // namespace dash::validation
