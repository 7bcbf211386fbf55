#pragma once
// Internal to the plan validator (plan_validator.h): the geometric part. The plan is sampled at every
// point and event time (at an event time twice: with the state just before the events and just after)
// and in between so finely that no point of a robot body or held object moves more than max_step
// between two samples (collision/segment_queries.h, segmentDisplacementBound). At every sample the
// robots, with what they hold, are checked against each other, obstacles and resting objects
// (collision/collision_queries.h); objects that rest are checked against each other once per epoch
// (they only move at events); objects held by two robots are checked for agreeing attachments.
#include <vector>

#include "engine/plan/plan_validator.h"
#include "engine/plan/validation_timeline.h"

namespace dash::validation {

/// Appends the problems found (one per colliding pair and stretch of time) and counts the samples.
void checkGeometry(const Plan& plan, const PlanMotion& motion, const Timeline& timeline,
                   const ValidationOptions& options, ValidationReport& report);

}  // namespace dash::validation
