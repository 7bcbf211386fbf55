#include "engine/conflict/step_scheduler.h"

#include <algorithm>
#include <cmath>

#include "engine/conflict/parking.h"

namespace dash {

const char* toString(ArrivalMode mode) {
  switch (mode) {
    case ArrivalMode::kTogether:
      return "together";
    case ArrivalMode::kGiverFirst:
      return "giver first";
    case ArrivalMode::kReceiverFirst:
      return "receiver first";
    case ArrivalMode::kComposite:
      return "composite";
  }
  return "?";
}

namespace {

/// Times from 0 of the waypoints of a Cartesian approach or retreat (StepVisit::approach, ::retreat):
/// every segment at the scheduler's speed, the whole stretched to a duration Scheduler::duration
/// would give one segment of its length (rounded up to the millisecond, at least min_segment) rather
/// than each of its many short segments rounded up on its own. A single point is held for min_segment.
std::vector<double> lineTimes(const Scene& scene, const SchedulerParams& params, int robot,
                              const std::vector<JointVector>& path) {
  const JointVector& vmax = scene.robots[robot].model->limits.velocity_max;
  std::vector<double> times{0.0};
  for (std::size_t w = 1; w < path.size(); ++w) {
    double t = 0.0;
    for (int i = 0; i < vmax.size(); ++i)
      t = std::max(t, std::abs(path[w][i] - path[w - 1][i]) / (params.velocity_scale * vmax[i]));
    times.push_back(times.back() + t);
  }
  if (path.size() < 2) return {0.0, params.min_segment};  // held still, as Scheduler::duration(q, q)
  const double exact = times.back();
  const double total = std::max(params.min_segment, std::ceil(exact * 1000.0) / 1000.0);
  const double n = static_cast<double>(times.size() - 1);
  for (std::size_t w = 1; w < times.size(); ++w) times[w] = exact > 0.0 ? times[w] * (total / exact) : total * w / n;
  times.back() = total;
  return times;
}

}  // namespace

// --- ScheduleBuild

std::vector<Aabb> ScheduleBuild::regionsFor(int robot, int step, const JointVector& q) const {
  return constraints ? constraints->regionsFor(plan, robot, step, q) : std::vector<Aabb>{};
}

std::vector<RobotState> ScheduleBuild::parkedAt(int self, double t) const {
  std::vector<RobotState> parked;
  for (const RobotTimeline& tl : state.timelines)
    if (tl.robot() != self && tl.end() <= t) parked.push_back({tl.robot(), tl.last(), tl.heldAtEnd()});
  return parked;
}

bool ScheduleBuild::fixNextTransit(int r) {
  auto& visits = motion.robots[r].visits;
  if (next_visit[r] >= visits.size()) return true;
  StepVisit& next = visits[next_visit[r]];
  const RobotTimeline& tl = state.timelines[r];
  if ((next.transit.front() - tl.last()).cwiseAbs().maxCoeff() <= 1e-12) return true;
  const MotionContext ctx{tl.heldAtEnd(), state.objects.layoutAt(tl.end()), {}};
  auto path = replan(r, tl.last(), next.transit.back(), ctx);
  if (!path) return false;
  next.transit = *path;
  return true;
}

bool ScheduleBuild::sendHome(int r) {
  const JointVector& home = scene.robots[r].home;
  std::vector<RobotTimeline>& timelines = state.timelines;
  if ((timelines[r].last() - home).cwiseAbs().maxCoeff() <= 1e-12) return false;
  const double start = timelines[r].end();
  const MotionContext ctx{timelines[r].heldAtEnd(), state.objects.layoutAt(start), parkedAt(r, start)};
  auto path = replan(r, timelines[r].last(), home, ctx);
  if (!path) return false;
  for (double t = start; t <= start + params.max_delay; t += params.delay_step) {
    RobotTimeline c = timelines[r];
    scheduler.appendPath(c, t, *path);
    if (checker.check(c, start, kForever, timelines, state.objects)) continue;
    timelines[r] = std::move(c);
    ++stats.replans;
    return fixNextTransit(r);
  }
  return false;
}

// --- StepScheduler

StepScheduler::StepScheduler(ScheduleBuild& build, const TaskPlan& plan, int step, const TransitionConfig& tc,
                             const TaskSpace& space)
    : b_(build), plan_(plan), space_(space), k_(step), a_(plan.steps[step].action), tc_(tc) {
  for (int role = 0; role < (a_.type == TaskArcType::kHandover ? 2 : 1); ++role) {
    const int r = role == 1 ? a_.robot2 : a_.robot;
    const StepVisit& visit = b_.motion.robots[r].visits[b_.next_visit[r]++];
    DASH_DEMAND(visit.step == k_);
    Participant p;
    p.robot = r;
    p.visit = &visit;
    p.transit = visit.transit;
    p.transit_time = b_.scheduler.pathDuration(r, visit.transit);
    p.approach_times = lineTimes(b_.scene, b_.params, r, visit.approach);
    p.approach_time = p.approach_times.back();
    parts_.push_back(std::move(p));
  }
  for (const Participant& p : parts_) {
    movers_.push_back(p.robot);
    max_approach_ = std::max(max_approach_, p.approach_time);
  }
}

void StepScheduler::appendApproach(RobotTimeline& c, const Participant& p, double T) const {
  const std::vector<JointVector>& approach = p.visit->approach;
  for (std::size_t w = 0; w < p.approach_times.size(); ++w)
    c.append(T - p.approach_time + p.approach_times[w], approach[std::min(w, approach.size() - 1)]);
}

int StepScheduler::modes() const { return parts_.size() == 2 && b_.params.staggered_arrivals ? 3 : 1; }

double StepScheduler::earliest() const {
  double t = 0.0;
  for (int d : plan_.steps[k_].after) t = std::max(t, b_.state.step_time[d] + b_.params.dwell);
  for (const Participant& p : parts_)
    t = std::max(t, b_.state.timelines[p.robot].end() + p.transit_time + p.approach_time);
  return t;
}

double StepScheduler::travel(int i, ArrivalMode mode) const {
  const int m = static_cast<int>(mode);
  return parts_[i].staggered[m].empty() ? parts_[i].transit_time : parts_[i].staggered_time[m];
}

double StepScheduler::windowWait(double T) const {
  double wait = 0.0;
  for (const Participant& p : parts_) {
    const double depart = T - p.approach_time - p.transit_time;
    wait = std::max(wait, b_.clearFrom(p.robot, k_, depart, T + b_.params.dwell - depart) - depart);
  }
  return wait;
}

std::vector<double> StepScheduler::arrivals(ArrivalMode mode, double T) const {
  std::vector<double> at;
  for (const Participant& p : parts_) at.push_back(T - p.approach_time);
  if (mode == ArrivalMode::kGiverFirst) at[0] = at[1] - travel(1, mode);  // giver in place before the receiver leaves
  if (mode == ArrivalMode::kReceiverFirst) {                             // receiver waits while the giver comes
    at[0] = at[1];
    at[1] = at[0] - travel(0, mode);
  }
  return at;
}

std::optional<std::vector<RobotTimeline>> StepScheduler::trial(ArrivalMode mode, double T) const {
  const std::vector<RobotTimeline>& timelines = b_.state.timelines;
  std::vector<RobotTimeline> trial = timelines;
  if (mode == ArrivalMode::kComposite) {
    const double depart = T - max_approach_ - composite_time_;
    for (int r : movers_)
      if (depart < timelines[r].end() - 1e-9) return std::nullopt;
    for (const Participant& p : parts_)
      if (b_.clearFrom(p.robot, k_, depart, T + b_.params.dwell - depart) > depart) return std::nullopt;
    for (std::size_t i = 0; i < movers_.size(); ++i) {
      RobotTimeline& c = trial[movers_[i]];
      c.append(depart, c.last());
      double t = depart;
      for (std::size_t w = 1; w < composite_->size(); ++w) {
        t += composite_steps_[w - 1];
        c.append(t, (*composite_)[w][i]);
      }
    }
    for (const Participant& p : parts_) appendApproach(trial[p.robot], p, T);
  } else {
    const int m = static_cast<int>(mode);
    const std::vector<double> arrive = arrivals(mode, T);
    for (std::size_t i = 0; i < parts_.size(); ++i)
      if (arrive[i] - travel(static_cast<int>(i), mode) < timelines[parts_[i].robot].end() - 1e-9) return std::nullopt;
    for (std::size_t i = 0; i < parts_.size(); ++i) {
      const Participant& p = parts_[i];
      RobotTimeline& c = trial[p.robot];
      const bool own = !p.staggered[m].empty();
      const std::vector<JointVector>& path = own ? p.staggered[m] : p.transit;
      const double depart = arrive[i] - (own ? p.staggered_time[m] : p.transit_time);
      if (b_.clearFrom(p.robot, k_, depart, T + b_.params.dwell - depart) > depart) return std::nullopt;
      c.append(depart, c.last());  // wait where it stands: always clear (its standing was checked)
      b_.scheduler.appendPath(c, depart, path);
      appendApproach(c, p, T);
    }
  }
  // The transition itself at time T.
  if (a_.type == TaskArcType::kPick) trial[a_.robot].grasp(T, {a_.object, tc_.X_TO});
  if (a_.type == TaskArcType::kPlace) trial[a_.robot].release(T);
  if (a_.type == TaskArcType::kHandover) {
    trial[a_.robot].release(T);
    trial[a_.robot2].grasp(T, {a_.object, tc_.X_TO2});
  }
  return trial;
}

std::optional<ScheduleConflict> StepScheduler::check(const std::vector<RobotTimeline>& trial, ArrivalMode mode,
                                                     double T) const {
  const std::vector<RobotTimeline>& timelines = b_.state.timelines;
  if (mode == ArrivalMode::kComposite) {
    for (const int r : movers_) {
      if (r == parts_[0].robot || (parts_.size() == 2 && r == parts_[1].robot)) continue;
      if (auto conflict = b_.checker.check(trial[r], timelines[r].end(), kForever, trial, b_.state.objects)) return conflict;
    }
  }
  for (const Participant& p : parts_)
    if (auto conflict = b_.checker.check(trial[p.robot], timelines[p.robot].end(), kForever, trial, b_.state.objects))
      return conflict;
  if (a_.type == TaskArcType::kPlace) return b_.checker.checkResting(a_.object, tc_.X_WO, T, trial, a_.robot);
  return std::nullopt;
}

bool StepScheduler::replanComposite() {
  ++composite_tries_;
  const std::vector<RobotTimeline>& timelines = b_.state.timelines;
  double depart = 0.0;
  for (int r : movers_) depart = std::max(depart, timelines[r].end());
  CompositeProblem problem;
  problem.robots = movers_;
  problem.layout = b_.state.objects.layoutAt(depart);
  // A robot in the way waits where it is clear of the participants' approach, transition and
  // retreat: its home if that is clear, else a parking configuration (parking.h).
  std::vector<RobotState> work;
  for (const Participant& p : parts_) {
    work.push_back({p.robot, p.visit->q_pre, p.visit->held_before});
    work.push_back({p.robot, p.visit->q, p.visit->held_before});
    work.push_back({p.robot, p.visit->q_post, p.visit->held_after});
  }
  const Scheduler& s = b_.scheduler;
  for (std::size_t i = 0; i < movers_.size(); ++i) {
    const int r = movers_[i];
    const HeldObject held = timelines[r].heldAtEnd();
    problem.start.push_back(timelines[r].last());
    problem.goal.push_back(i < parts_.size() ? parts_[i].visit->q_pre
                           : b_.params.parking ? parkingConfiguration(*s.world_, *s.context_, r, held, work, problem.layout)
                                               : b_.scene.robots[r].home);
    problem.held.push_back(held);
  }
  for (const RobotState& st : b_.parkedAt(-1, depart))
    if (std::find(movers_.begin(), movers_.end(), st.robot) == movers_.end()) problem.parked.push_back(st);
  CompositeParams cp;
  cp.iterations = b_.params.composite_iterations;
  composite_ = planComposite(*s.world_, *s.context_, problem, cp, b_.deadline);
  if (!composite_) return false;
  composite_steps_ = s.compositeDurations(movers_, *composite_);
  composite_time_ = 0.0;
  for (double d : composite_steps_) composite_time_ += d;
  ++b_.stats.composite_replans;
  return true;
}

// Replans the participants' transits for an arrival mode around the robots standing still and the
// partner: arriving together, each avoids the partner where it stands now; staggered, whoever goes
// first avoids the partner where it stands now and whoever goes second avoids the first one in its
// place (the giver at the handover pose with the object, the receiver at its approach start).
void StepScheduler::replanTransits(ArrivalMode mode) {
  const int m = static_cast<int>(mode);
  const int first = mode == ArrivalMode::kGiverFirst ? 0 : 1;
  const std::vector<RobotTimeline>& timelines = b_.state.timelines;
  for (int i = 0; i < static_cast<int>(parts_.size()); ++i) {
    Participant& p = parts_[i];
    if (p.transit.size() < 2) continue;
    const double depart = timelines[p.robot].end();
    // Every robot whose schedule has ended stands still from now on, blockers included.
    std::vector<RobotState> parked = b_.parkedAt(p.robot, depart);
    std::erase_if(parked, [&](const RobotState& st) {
      return std::any_of(parts_.begin(), parts_.end(), [&](const Participant& q) { return q.robot == st.robot; });
    });
    for (int blocker : blockers_)
      if (std::none_of(parked.begin(), parked.end(), [&](const RobotState& st) { return st.robot == blocker; }))
        parked.push_back({blocker, timelines[blocker].last(), timelines[blocker].heldAtEnd()});
    if (parts_.size() == 2 && (m > 0 || parts_[0].staggered_tried[0])) {
      const Participant& other = parts_[1 - i];
      if (i == first || m == 0) {
        parked.push_back({other.robot, timelines[other.robot].last(), timelines[other.robot].heldAtEnd()});
      } else {
        const bool other_is_giver = i == 1;
        parked.push_back({other.robot, other_is_giver ? other.visit->q : other.visit->q_pre,
                          other_is_giver ? other.visit->held_before : HeldObject{}});
      }
    }
    const MotionContext ctx{timelines[p.robot].heldAt(depart), b_.state.objects.layoutAt(depart), parked,
                            b_.regionsFor(p.robot, k_, p.visit->q)};
    auto path = b_.replan(p.robot, p.transit.front(), p.transit.back(), ctx);
    if (!path) continue;
    ++b_.stats.replans;
    if (m == 0) {
      p.transit = *path;
      p.transit_time = b_.scheduler.pathDuration(p.robot, *path);
    } else {
      p.staggered[m] = *path;
      p.staggered_time[m] = b_.scheduler.pathDuration(p.robot, *path);
    }
  }
}

StepScheduler::Repair StepScheduler::repair(const ScheduleConflict& conflict, ArrivalMode mode) {
  const std::vector<RobotTimeline>& timelines = b_.state.timelines;
  const int m = static_cast<int>(mode);
  const bool with_partner =
      parts_.size() == 2 && (conflict.other == parts_[0].robot || conflict.other == parts_[1].robot);
  // A conflict among the robots of this step (participants, and the movers of its composite
  // subproblem) is not one with a robot standing in the way.
  const bool internal =
      with_partner || std::find(movers_.begin(), movers_.end(), conflict.other) != movers_.end();
  const bool standing = conflict.other >= 0 && timelines[conflict.other].end() <= conflict.t;
  // Retiming alone (conflict_replanning off): no repair replans a motion.
  if (!b_.params.conflict_replanning) return Repair::kNone;
  // 1. The partner in the way: the same arrival mode again, with transits replanned around it.
  if (with_partner && mode != ArrivalMode::kComposite && !parts_[0].staggered_tried[m]) {
    parts_[0].staggered_tried[m] = true;
    replanTransits(mode);
    return Repair::kSameModeAgain;
  }
  // 2. Another robot standing still in the way (its schedule has ended) will not move before this
  // step is done: waiting cannot help, so move around it.
  if (standing && !internal && std::find(blockers_.begin(), blockers_.end(), conflict.other) == blockers_.end()) {
    blockers_.push_back(conflict.other);
    replanTransits(ArrivalMode::kTogether);
    for (ArrivalMode staggered : {ArrivalMode::kGiverFirst, ArrivalMode::kReceiverFirst})
      if (parts_[0].staggered_tried[static_cast<int>(staggered)]) replanTransits(staggered);
    return Repair::kSameModeAgain;
  }
  // 3. Moving around it did not help (gantries share one rail; an arm may stand right over the spot):
  // send the idle robot home first.
  if (b_.params.idle_arms_home && standing && !internal &&
      std::find(evicted_.begin(), evicted_.end(), conflict.other) == evicted_.end()) {
    evicted_.push_back(conflict.other);
    if (b_.sendHome(conflict.other)) return Repair::kSameModeAgain;
  }
  // 4. The composite path itself in conflict among its movers: the checker's time cuts sample the
  // motion at other instants than the planner did and found a graze. Plan it again.
  if (mode == ArrivalMode::kComposite && internal && composite_tries_ < b_.params.composite_attempts &&
      replanComposite())
    return Repair::kComposite;
  // 5. Still in conflict with the partner or with a robot standing still: plan the robots involved
  // together (ARC), adding the robot in the way to the subproblem.
  if ((standing || (with_partner && m >= modes() - 1)) && composite_tries_ < b_.params.composite_attempts) {
    const bool known = std::find(movers_.begin(), movers_.end(), conflict.other) != movers_.end();
    if (!known && standing && static_cast<int>(movers_.size()) < b_.params.max_composite_robots)
      movers_.push_back(conflict.other);
    if ((!known || !composite_) && replanComposite()) return Repair::kComposite;
  }
  return Repair::kNone;
}

bool StepScheduler::commit(std::vector<RobotTimeline> trial, ArrivalMode mode, double T, std::string& why) {
  b_.state.timelines = std::move(trial);
  // Robots that stepped aside continue from where they now stand.
  for (std::size_t i = parts_.size(); mode == ArrivalMode::kComposite && i < movers_.size(); ++i)
    if (!b_.fixNextTransit(movers_[i])) {
      why = "no path after " + b_.scene.robots[movers_[i]].id + " stepped aside";
      return false;
    }
  if (a_.type == TaskArcType::kPick) b_.state.objects.pick(a_.object, T);
  if (a_.type == TaskArcType::kPlace) b_.state.objects.place(a_.object, T, tc_.X_WO);
  b_.state.step_time[k_] = T;
  T_ = T;
  return true;
}

std::string StepScheduler::lastConflictText() const {
  if (!last_conflict_) return "?";
  const ScheduleConflict& c = *last_conflict_;
  const Scene& scene = b_.scene;
  std::string what = c.object >= 0 ? "object " + scene.objects[c.object].id
                                   : (c.other >= 0 ? "robot " + scene.robots[c.other].id : std::string("an obstacle"));
  if (c.robot >= 0) what = scene.robots[c.robot].id + " against " + what;
  return what;
}

std::optional<std::string> StepScheduler::place() {
  const double start = earliest();
  double T = start;
  double give_up = T + b_.params.max_delay;
  while (T <= give_up) {
    // A clock-time window (StepWindow) the step would overlap: it waits until the window has passed.
    if (const double wait = windowWait(T); wait > 0.0) {
      if (!std::isfinite(wait)) break;
      T += wait;
      give_up = std::max(give_up, T + b_.params.max_delay);
      continue;
    }
    std::optional<ScheduleConflict> round_conflict;
    std::optional<RobotTimeline> round_robot, round_other;
    for (int m = 0; m < kArrivalModeCount;) {
      if (b_.deadline.expired()) return std::string("deadline");
      const ArrivalMode mode = static_cast<ArrivalMode>(m);
      if (mode == ArrivalMode::kComposite ? !composite_ : m >= modes()) {
        ++m;
        continue;
      }
      std::optional<std::vector<RobotTimeline>> placed = trial(mode, T);
      if (!placed) {  // the mode does not fit at this T
        ++m;
        continue;
      }
      const std::optional<ScheduleConflict> conflict = check(*placed, mode, T);
      if (!conflict) {
        std::string why;
        if (!commit(std::move(*placed), mode, T, why)) return why;
        return std::nullopt;
      }
      switch (repair(*conflict, mode)) {
        case Repair::kSameModeAgain:
          break;
        case Repair::kComposite:
          m = static_cast<int>(ArrivalMode::kComposite);
          break;
        case Repair::kNone:
          round_conflict = conflict;
          if (conflict->robot >= 0) round_robot = (*placed)[static_cast<std::size_t>(conflict->robot)];
          if (conflict->other >= 0) round_other = (*placed)[static_cast<std::size_t>(conflict->other)];
          ++m;
          break;
      }
    }
    if (round_conflict) {
      last_conflict_ = round_conflict;
      last_robot_ = std::move(round_robot);
      last_other_ = std::move(round_other);
      ++b_.stats.delays;
      // Waiting for a robot that is still busy (moving, or waiting in its own schedule for a later
      // step) does not count against max_delay: once its schedule has ended it stands still, and the
      // repairs for a robot standing in the way (move around it, send it home, plan together) apply.
      const int other = round_conflict->other;
      if (other >= 0 && b_.state.timelines[other].end() > T)
        give_up = std::max(give_up, b_.state.timelines[other].end() + b_.params.max_delay);
    }
    T += b_.params.delay_step;  // retiming: every mode was in conflict (or none fitted yet)
  }
  return "could not schedule step " + std::to_string(k_) + " (" + describeStep(plan_.steps[k_], space_) + ") within " +
         std::to_string(static_cast<int>(give_up - start)) + " s of delay; last conflict: " + lastConflictText();
}

bool StepScheduler::finish(std::string& why) {
  const Scene& scene = b_.scene;
  const double T = T_;
  std::vector<PlanEvent>& events = b_.state.events;
  // Events: the receiver grasps at T and the giver lets go at the same instant (formats.md allows it).
  const std::string& actor_id = scene.robots[a_.robot].id;
  switch (a_.type) {
    case TaskArcType::kPick:
      events.push_back({PlanEvent::Type::kGrasp, T, actor_id, scene.objects[a_.object].id, tc_.X_TO, -1});
      break;
    case TaskArcType::kPlace:
      events.push_back({PlanEvent::Type::kRelease, T, actor_id, scene.objects[a_.object].id, Pose::Identity(), -1});
      break;
    case TaskArcType::kHandover:
      events.push_back(
          {PlanEvent::Type::kGrasp, T, scene.robots[a_.robot2].id, scene.objects[a_.object].id, tc_.X_TO2, -1});
      events.push_back({PlanEvent::Type::kRelease, T, actor_id, scene.objects[a_.object].id, Pose::Identity(), -1});
      break;
    case TaskArcType::kInspect:
      events.push_back({PlanEvent::Type::kInspect, T, actor_id, "", Pose::Identity(), a_.task});
      break;
    default:
      break;
  }
  // Retreats, giver first: each leaves after the gripper has closed or opened, as soon as it is clear.
  std::vector<RobotTimeline>& timelines = b_.state.timelines;
  for (const Participant& p : parts_) {
    const StepVisit& v = *p.visit;
    if ((v.q_post - v.q).cwiseAbs().maxCoeff() < 1e-12) continue;
    const std::vector<double> times = lineTimes(scene, b_.params, p.robot, v.retreat);
    for (double rho = T + b_.params.dwell; rho <= T + b_.params.max_delay; rho += b_.params.delay_step) {
      RobotTimeline c = timelines[p.robot];
      c.append(rho, v.q);
      for (std::size_t w = 1; w < v.retreat.size(); ++w) c.append(rho + times[w], v.retreat[w]);
      if (!b_.checker.check(c, timelines[p.robot].end(), kForever, timelines, b_.state.objects)) {
        timelines[p.robot] = std::move(c);
        break;
      }
      ++b_.stats.delays;
    }
    // If no retreat was clear the robot stays at q (already checked) and leaves from there.
  }
  // The next visit's transit must start where this robot now stands.
  for (const Participant& p : parts_)
    if (!b_.fixNextTransit(p.robot)) {
      why = "no path after a skipped retreat of " + scene.robots[p.robot].id;
      return false;
    }
  return true;
}

}  // namespace dash
