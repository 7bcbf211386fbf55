#pragma once
// How DaSH turns a failed schedule, or a contact the plan validator finds, into a CBS-MP conflict
// (dash_run.h): the plan step it belongs to and one constraint per robot involved
// (motion_constraint.h).
#include <optional>
#include <string>
#include <vector>

#include "engine/conflict/conflict_region.h"
#include "engine/dash/motion_hypergraph.h"
#include "engine/dash/plan_extraction.h"
#include "engine/dash/resting_conflicts.h"
#include "engine/plan/plan_validator.h"

namespace dash {

/// The conflict a failed schedule (or a contact the validator found) reports at plan step `step`
/// (-1: the ways home), with CBS-MP's one constraint per robot of the conflict. With `timing` (the two
/// robots, the steps they were in and the interval [t_begin, t_end] of what could not be resolved): a
/// constraint for each robot on its last move into that step (its transition when it did not move;
/// its way home at step -1) over [t_begin, t_end]. Without (nothing timed was learned): the step's
/// participants' last moves over the whole plan.
MotionConflict scheduleConflict(const MotionHypergraph& graph, const ExtractedPlan& plan, int step,
                                const std::string& why, const std::optional<ConflictRegion>& timing = {});

/// The robots, steps and interval of a contact the validator found in a schedule whose steps happen at
/// `step_times`: each robot's step is the first of its steps that has not ended (transition plus
/// `dwell`) at the contact's time, else its way home (-1); the interval is [t, max(t_end, t + min_window)].
/// nullopt when it is not a contact between known robots.
std::optional<ConflictRegion> contactTiming(const Scene& scene, const TaskPlan& plan,
                                            const std::vector<double>& step_times, const ValidationProblem& problem,
                                            double dwell, double min_window);

/// A collision between robots, held objects or resting objects (what conflict resolution checks).
bool isContact(const ValidationProblem& problem);

/// The plan step a contact the validator found belongs to: the first transition at or after it of a
/// robot involved (the move into it is where the contact was), else the last before it; -1: none.
int contactStep(const Scene& scene, const TaskPlan& plan, const std::vector<double>& step_times,
                const ValidationProblem& problem);

}  // namespace dash
