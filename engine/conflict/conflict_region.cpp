#include "engine/conflict/conflict_region.h"

#include <algorithm>

#include "engine/collision/region_queries.h"
#include "engine/collision/segment_queries.h"

namespace dash {

namespace {

Aabb grownBy(const Aabb& box, double margin) { return Aabb(box.min().array() - margin, box.max().array() + margin); }

bool takesPart(const TaskArc& a, int robot) { return a.robot == robot || a.robot2 == robot; }

/// Per part of robot `other` (bodies, then its held object): a box containing it over [t0, t1] of its
/// timeline, cut at the timeline's breakpoints.
std::vector<Aabb> sweptParts(const CollisionWorld& world, CollisionContext& context, const RobotTimeline& timeline,
                             double t0, double t1) {
  std::vector<double> cuts{t0};
  timeline.breakpoints(t0, t1, cuts);
  cuts.push_back(t1);
  std::vector<Aabb> parts, piece;
  for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
    piece.clear();
    sweptPartBoxes(world, context, RobotState{timeline.robot(), timeline.at(cuts[i]), timeline.heldAt(cuts[i])},
                   timeline.at(cuts[i + 1]), piece);
    if (parts.size() < piece.size()) parts.resize(piece.size(), Aabb());  // a grasp adds the held part
    for (std::size_t p = 0; p < piece.size(); ++p) parts[p].extend(piece[p]);
  }
  std::erase_if(parts, [](const Aabb& b) { return b.isEmpty(); });
  return parts;
}

/// The parts of `other` whose boxes (grown by the clearance) meet one of `self`'s; all of them if none do.
std::vector<Aabb> collidingParts(std::vector<Aabb> other, const std::vector<Aabb>& self, double clearance) {
  std::vector<Aabb> meeting;
  for (const Aabb& o : other)
    for (const Aabb& s : self)
      if (grownBy(o, clearance).intersects(s)) {
        meeting.push_back(o);
        break;
      }
  return meeting.empty() ? other : meeting;
}

/// Whether robot r, where its schedule in `state` ends (where its next move starts), may be inside `boxes`.
bool startsInside(const CollisionWorld& world, CollisionContext& context, const ScheduleState& state, int r,
                  const std::vector<Aabb>& boxes) {
  const RobotTimeline& t = state.timelines[static_cast<std::size_t>(r)];
  return robotEntersRegions(world, context, RobotState{r, t.last(), t.heldAtEnd()}, boxes);
}

Aabb objectBox(const CollisionWorld& world, int object, const Pose& X_WO) {
  return boxAabb(X_WO, 0.5 * world.scene().objects[static_cast<std::size_t>(object)].shape.size);
}

}  // namespace

int stepOfRobotAt(const TaskPlan& plan, const std::vector<double>& step_times, int robot, double t) {
  int after = -1, before = -1;
  for (int k = 0; k < static_cast<int>(plan.steps.size()) && k < static_cast<int>(step_times.size()); ++k) {
    if (!takesPart(plan.steps[k].action, robot)) continue;
    if (step_times[k] >= t && (after < 0 || step_times[k] < step_times[after])) after = k;
    if (step_times[k] < t && (before < 0 || step_times[k] > step_times[before])) before = k;
  }
  return after >= 0 ? after : before;
}

std::optional<ConflictRegion> conflictRegion(const CollisionWorld& world, CollisionContext& context,
                                             const ScheduleState& state, const TaskPlan& plan, int failed_step,
                                             const std::vector<TransitionConfig>& transitions,
                                             const ScheduleConflict& conflict, TrialTimelines trial, double window) {
  const TransitionConfig& tc = transitions[static_cast<std::size_t>(failed_step)];
  // Only the steps placed so far have times.
  const std::vector<double> placed(state.step_time.begin(), state.step_time.begin() + failed_step);
  ConflictRegion region;
  region.t_begin = conflict.t;
  region.t_end = conflict.t + window;
  region.object = conflict.object;
  const TaskArc& failed = plan.steps[static_cast<std::size_t>(failed_step)].action;
  if (conflict.robot >= 0) {  // a move of a robot being placed met another robot or a resting object
    region.robot = conflict.robot;
    region.step = takesPart(failed, conflict.robot) ? failed_step : stepOfRobotAt(plan, placed, conflict.robot, conflict.t);
    if (conflict.other >= 0) {
      region.other = conflict.other;
      region.other_step = takesPart(failed, conflict.other) ? failed_step : stepOfRobotAt(plan, placed, conflict.other, conflict.t);
      // Both robots where the trial that met the conflict had them (a handover's partner moves with it).
      const RobotTimeline& other =
          trial.other != nullptr ? *trial.other : state.timelines[static_cast<std::size_t>(conflict.other)];
      const RobotTimeline& self =
          trial.robot != nullptr ? *trial.robot : state.timelines[static_cast<std::size_t>(conflict.robot)];
      const std::vector<Aabb> other_parts = sweptParts(world, context, other, region.t_begin, region.t_end);
      const std::vector<Aabb> self_parts = sweptParts(world, context, self, region.t_begin, region.t_end);
      region.boxes = collidingParts(other_parts, self_parts, world.clearance());
      // A robot that stands where the other came to (its move starts inside the region) cannot go
      // around it: when the other is the step's partner, its move goes around this one's parts instead.
      if (takesPart(failed, conflict.other) && startsInside(world, context, state, conflict.robot, region.boxes)) {
        std::vector<Aabb> swapped = collidingParts(self_parts, other_parts, world.clearance());
        if (!startsInside(world, context, state, conflict.other, swapped)) {
          std::swap(region.robot, region.other);
          std::swap(region.step, region.other_step);
          region.boxes = std::move(swapped);
        }
      }
    } else if (conflict.object >= 0) {
      const ObjectLayout layout = state.objects.layoutAt(conflict.t);
      if (!layout.isPresent(conflict.object)) return std::nullopt;
      region.boxes = {objectBox(world, conflict.object, layout.X_WO[static_cast<std::size_t>(conflict.object)])};
    }
  } else if (conflict.other >= 0 && failed.type == TaskArcType::kPlace && conflict.object == failed.object) {
    // The object placed by the failed step is where robot `other` passes: that robot goes around it.
    region.robot = conflict.other;
    region.step = stepOfRobotAt(plan, placed, conflict.other, conflict.t);
    region.boxes = {objectBox(world, conflict.object, tc.X_WO)};
  }
  if (region.robot < 0 || region.step < 0 || region.boxes.empty()) return std::nullopt;
  const TaskArc& at = plan.steps[static_cast<std::size_t>(region.step)].action;
  const TransitionConfig& at_tc = transitions[static_cast<std::size_t>(region.step)];
  region.q = at.robot2 == region.robot ? at_tc.q2 : at_tc.q;
  for (Aabb& box : region.boxes) box = grownBy(box, world.clearance());
  return region;
}

}  // namespace dash
