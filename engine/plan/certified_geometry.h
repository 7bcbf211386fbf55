#pragma once
// Internal to the plan validator (plan_validator.h): the certified geometric check.
//
// Between two consecutive point or event times every robot moves on one straight joint-space segment
// and nothing else changes (the epoch: who holds what, where the rest lie). For every pair of parts
// that must stay apart, conservative advancement walks the stretch: at fraction u it measures the
// pair's signed distance d (FCL, exact shapes); no point of either part moves more than `rate` per
// unit of u (per-body bounds from the kinematic chain's link lengths and the joint deltas,
// segment_queries.h), so the pair keeps more than the clearance c until u + (d - c) / rate. That
// instant is measured next. A stretch shorter than certify_floor of motion is not split further.
// When d < c the pair is in contact until at least u + (c - d) / rate, so contacts are followed the
// same way, and the report gives the two parts, the stretch and the smallest distance (depth).
//
// Parts and pairs (formats.md):
//  - robot bodies: against obstacles, resting objects, other robots' bodies and held objects, and the
//    model's self-collision pairs;
//  - a held object: against obstacles, resting objects, its robot's non-gripper bodies, other robots'
//    bodies (but the gripper of a second holder: a handover) and other held objects.
// Contact is allowed only where it is meant (collision_world.h): a gripper body against a resting
// object's contact box; a held object against what it rests on where it is picked up or put down
// (the obstacles and objects within the contact tolerance of it at those two poses), with its lowest
// face raised by the tolerance. Those pairs are checked for overlap only; every other pair must keep
// `clearance` apart. Two shapes that touch within kTouchTolerance do not overlap.
//
// Boxes first: a part's swept box over the stretch (its boxes at both ends grown by half its bound)
// rules out most pairs before any distance is measured, and an axis-aligned box distance stands in
// for the exact one while it already certifies the rest of the stretch.
#include <vector>

#include "engine/plan/plan_validator.h"
#include "engine/plan/validation_timeline.h"

namespace dash::validation {

/// m: signed distances above minus this are touching, not overlapping (FCL's numerical noise).
inline constexpr double kTouchTolerance = 1e-6;

/// Appends one problem per pair and stretch of contact (or of clearance violated), and fills
/// report.closest, report.pairs and report.samples (distance evaluations).
void checkGeometryCertified(const Plan& plan, const PlanMotion& motion, const Timeline& timeline,
                            const ValidationOptions& options, ValidationReport& report);

}  // namespace dash::validation
