#pragma once
// How DaSH turns a failed schedule, or a contact the plan validator finds, into a CBS-MP conflict
// (dash_run.h): the plan step it belongs to and one constraint per robot involved
// (motion_constraint.h).
#include <string>
#include <vector>

#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/plan_extraction.h"
#include "engine/dash/resting_conflicts.h"
#include "engine/plan/plan_validator.h"

namespace dash {

/// The conflict a failed schedule (or a contact the validator found) reports at plan step `step`:
/// for each participant, the last move into the step (its transition when it did not move), not to be
/// traversed while the object or partner of the step waits in the state the step consumes (CBS-MP:
/// one constraint per robot in the conflict). Step -1: the ways home, at any time.
MotionConflict scheduleConflict(const MotionHypergraph& graph, const ExtractedPlan& plan, int step,
                                const std::string& why);

/// A collision between robots, held objects or resting objects (what conflict resolution checks).
bool isContact(const ValidationProblem& problem);

/// The plan step a contact the validator found belongs to: the first transition at or after it of a
/// robot involved (the move into it is where the contact was), else the last before it; -1: none.
int contactStep(const Scene& scene, const TaskPlan& plan, const std::vector<double>& step_times,
                const ValidationProblem& problem);

}  // namespace dash
