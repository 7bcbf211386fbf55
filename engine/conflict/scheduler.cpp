#include "engine/conflict/scheduler.h"

#include <algorithm>
#include <cmath>

#include "engine/conflict/parking.h"

namespace dash {

namespace {

struct Participant {
  int robot = -1;
  const StepVisit* visit = nullptr;
  std::vector<JointVector> transit;
  double transit_time = 0.0;
  double approach_time = 0.0;
  /// Handover arrival modes 1 and 2 (one robot in place first): transits replanned around the partner.
  std::vector<JointVector> staggered[3];
  double staggered_time[3] = {0.0, 0.0, 0.0};
  bool staggered_tried[3] = {false, false, false};
};

ObjectLayout startLayout(const TaskSpace& space) {
  ObjectLayout layout = ObjectLayout::atStart(space.scene());
  for (int o = 0; o < space.objectCount(); ++o) layout.place(o, space.location(o, space.startLocation(o)).X_WO);
  return layout;
}

}  // namespace

void applySchedulerParameters(SchedulerParams& params, const ParamValues& values) {
  const std::pair<const char*, bool*> flags[] = {{"staggered_arrivals", &params.staggered_arrivals},
                                                 {"idle_arms_home", &params.idle_arms_home},
                                                 {"parking", &params.parking},
                                                 {"schedule_memo", &params.schedule_memo}};
  for (const auto& [name, field] : flags)
    if (values.contains(name)) *field = paramBool(values, name);
}

Scheduler::Scheduler(const CollisionWorld& world, CollisionContext& context, SchedulerParams params)
    : world_(&world), context_(&context), params_(params), checker_(world, context) {}

double Scheduler::duration(int robot, const JointVector& a, const JointVector& b) const {
  const JointVector& vmax = world_->scene().robots[robot].model->limits.velocity_max;
  double t = 0.0;
  for (int i = 0; i < a.size(); ++i) t = std::max(t, std::abs(b[i] - a[i]) / (params_.velocity_scale * vmax[i]));
  // Round up to the millisecond so that times written to the plan keep every speed within limits.
  return std::max(params_.min_segment, std::ceil(t * 1000.0) / 1000.0);
}

std::vector<double> Scheduler::compositeDurations(const std::vector<int>& robots, const CompositePath& path) const {
  std::vector<double> out;
  for (std::size_t w = 1; w < path.size(); ++w) {
    double d = 0.0;
    for (std::size_t i = 0; i < robots.size(); ++i) d = std::max(d, duration(robots[i], path[w - 1][i], path[w][i]));
    out.push_back(d);
  }
  return out;
}

double Scheduler::pathDuration(int robot, const std::vector<JointVector>& path) const {
  double t = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) t += duration(robot, path[i - 1], path[i]);
  return t;
}

void Scheduler::appendPath(RobotTimeline& timeline, double start, const std::vector<JointVector>& path) const {
  double t = start;
  timeline.append(t, path.front());
  for (std::size_t i = 1; i < path.size(); ++i) {
    t += duration(timeline.robot(), path[i - 1], path[i]);
    timeline.append(t, path[i]);
  }
}

ScheduleResult Scheduler::build(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                MotionLayerResult motion, const TaskSpace& space, const MoveReplanner& replan,
                                const Deadline& deadline) {
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  ScheduleResult result;
  ScheduleState state{{}, ObjectTimeline(startLayout(space)), {}, std::vector<double>(plan.steps.size(), 0.0)};
  for (int r = 0; r < robots; ++r) state.timelines.emplace_back(r, scene.robots[r].home);
  std::vector<RobotTimeline>& timelines = state.timelines;
  ObjectTimeline& objects = state.objects;
  std::vector<PlanEvent>& events = state.events;
  std::vector<double>& step_time = state.step_time;
  std::vector<std::size_t> next_visit(static_cast<std::size_t>(robots), 0);
  const std::uint64_t checks_before = context_->counters().configuration_checks;

  auto fail = [&](int step, std::string why) {
    memo_.recordEnd(state);
    result.ok = false;
    result.failed_step = step;
    result.reason = std::move(why);
    result.stats.checks = static_cast<std::int64_t>(context_->counters().configuration_checks - checks_before);
    return result;
  };
  // The other robots standing still from time t on (their schedules end before t), for replanning.
  auto parkedAt = [&](int self, double t) {
    std::vector<RobotState> parked;
    for (const RobotTimeline& tl : timelines)
      if (tl.robot() != self && tl.end() <= t) parked.push_back({tl.robot(), tl.last(), tl.heldAtEnd()});
    return parked;
  };

  // The next visit's transit must start where the robot now stands (after a skipped retreat or an
  // eviction): replan it from there.
  auto fixNextTransit = [&](int r) {
    auto& visits = motion.robots[r].visits;
    if (next_visit[r] >= visits.size()) return true;
    StepVisit& next = visits[next_visit[r]];
    if ((next.transit.front() - timelines[r].last()).cwiseAbs().maxCoeff() <= 1e-12) return true;
    const MotionContext ctx{timelines[r].heldAtEnd(), objects.layoutAt(timelines[r].end()), {}};
    auto path = replan(r, timelines[r].last(), next.transit.back(), ctx);
    if (!path) return false;
    next.transit = *path;
    return true;
  };
  // Moves an idle robot from where it stands to its home configuration, as soon as that is clear.
  auto sendHome = [&](int r) {
    const JointVector& home = scene.robots[r].home;
    if ((timelines[r].last() - home).cwiseAbs().maxCoeff() <= 1e-12) return false;
    const double start = timelines[r].end();
    const MotionContext ctx{timelines[r].heldAtEnd(), objects.layoutAt(start), parkedAt(r, start)};
    auto path = replan(r, timelines[r].last(), home, ctx);
    if (!path) return false;
    for (double t = start; t <= start + params_.max_delay; t += params_.delay_step) {
      RobotTimeline c = timelines[r];
      appendPath(c, t, *path);
      if (checker_.check(c, start, kForever, timelines, objects)) continue;
      timelines[r] = std::move(c);
      ++result.stats.replans;
      return fixNextTransit(r);
    }
    return false;
  };

  // The steps this plan shares with the last one built are taken as they were scheduled then.
  const int shared = params_.schedule_memo ? memo_.resume(plan, transitions, state) : 0;
  memo_.restart(shared);
  result.stats.reused_steps = shared;
  for (int k = 0; k < shared; ++k) {
    const TaskArc& a = plan.steps[k].action;
    ++next_visit[a.robot];
    if (a.type == TaskArcType::kHandover) ++next_visit[a.robot2];
  }
  for (int r = 0; r < robots && shared > 0; ++r)
    if (!fixNextTransit(r)) return fail(shared, "no path for " + scene.robots[r].id + " on from the shared steps");

  for (int k = shared; k < static_cast<int>(plan.steps.size()); ++k) {
    const TaskArc& a = plan.steps[k].action;
    const TransitionConfig& tc = transitions[k];
    std::vector<Participant> parts;
    for (int role = 0; role < (a.type == TaskArcType::kHandover ? 2 : 1); ++role) {
      const int r = role == 1 ? a.robot2 : a.robot;
      const StepVisit& visit = motion.robots[r].visits[next_visit[r]++];
      DASH_DEMAND(visit.step == k);
      parts.push_back({r, &visit, visit.transit, pathDuration(r, visit.transit), duration(r, visit.q_pre, visit.q)});
    }
    double t_dep = 0.0;
    for (int d : plan.steps[k].after) t_dep = std::max(t_dep, step_time[d] + params_.dwell);
    auto earliest = [&] {
      double t = t_dep;
      for (const Participant& p : parts) t = std::max(t, timelines[p.robot].end() + p.transit_time + p.approach_time);
      return t;
    };
    double T = earliest();
    const double give_up = T + params_.max_delay;
    bool scheduled = false;
    std::optional<ScheduleConflict> last_conflict;
    std::vector<int> blockers;  // robots found standing in the way of this step
    std::vector<int> evicted;   // idle robots sent home to clear the way for this step
    // ARC's subproblem for this step: the participants first, then robots standing in their way.
    std::vector<int> movers;
    for (const Participant& p : parts) movers.push_back(p.robot);
    std::optional<CompositePath> composite;
    std::vector<double> composite_steps;
    double composite_time = 0.0;
    int composite_tries = 0;
    double max_approach = 0.0;
    for (const Participant& p : parts) max_approach = std::max(max_approach, p.approach_time);
    // Plans the movers together from where they stand: participants to their approach starts, the
    // others to their home configurations.
    auto replanComposite = [&]() {
      ++composite_tries;
      double depart = 0.0;
      for (int r : movers) depart = std::max(depart, timelines[r].end());
      CompositeProblem problem;
      problem.robots = movers;
      problem.layout = objects.layoutAt(depart);
      // A robot in the way waits where it is clear of the participants' approach, transition and
      // retreat: its home if that is clear, else a parking configuration (parking.h).
      std::vector<RobotState> work;
      for (const Participant& p : parts) {
        work.push_back({p.robot, p.visit->q_pre, p.visit->held_before});
        work.push_back({p.robot, p.visit->q, p.visit->held_before});
        work.push_back({p.robot, p.visit->q_post, p.visit->held_after});
      }
      for (std::size_t i = 0; i < movers.size(); ++i) {
        const int r = movers[i];
        const HeldObject held = timelines[r].heldAtEnd();
        problem.start.push_back(timelines[r].last());
        problem.goal.push_back(i < parts.size() ? parts[i].visit->q_pre
                               : params_.parking ? parkingConfiguration(*world_, *context_, r, held, work, problem.layout)
                                                 : scene.robots[r].home);
        problem.held.push_back(held);
      }
      for (const RobotState& st : parkedAt(-1, depart))
        if (std::find(movers.begin(), movers.end(), st.robot) == movers.end()) problem.parked.push_back(st);
      CompositeParams cp;
      cp.iterations = params_.composite_iterations;
      composite = planComposite(*world_, *context_, problem, cp, deadline);
      if (!composite) return false;
      composite_steps = compositeDurations(movers, *composite);
      composite_time = 0.0;
      for (double d : composite_steps) composite_time += d;
      ++result.stats.composite_replans;
      return true;
    };
    // Replans the participants' transits for an arrival mode around the robots standing still and the
    // partner: arriving together, each avoids the partner where it stands now; staggered, whoever goes
    // first avoids the partner where it stands now and whoever goes second avoids the first one in its
    // place (the giver at the handover pose with the object, the receiver at its approach start).
    auto replanTransits = [&](int mode) {
      const int first = mode == 1 ? 0 : 1;
      for (int i = 0; i < static_cast<int>(parts.size()); ++i) {
        Participant& p = parts[i];
        if (p.transit.size() < 2) continue;
        const double depart = timelines[p.robot].end();
        // Every robot whose schedule has ended stands still from now on, blockers included.
        std::vector<RobotState> parked = parkedAt(p.robot, depart);
        std::erase_if(parked, [&](const RobotState& st) {
          return std::any_of(parts.begin(), parts.end(), [&](const Participant& q) { return q.robot == st.robot; });
        });
        for (int b : blockers)
          if (std::none_of(parked.begin(), parked.end(), [&](const RobotState& st) { return st.robot == b; }))
            parked.push_back({b, timelines[b].last(), timelines[b].heldAtEnd()});
        if (parts.size() == 2 && (mode > 0 || parts[0].staggered_tried[0])) {
          const Participant& other = parts[1 - i];
          if (i == first || mode == 0) {
            parked.push_back({other.robot, timelines[other.robot].last(), timelines[other.robot].heldAtEnd()});
          } else {
            const bool other_is_giver = i == 1;
            parked.push_back({other.robot, other_is_giver ? other.visit->q : other.visit->q_pre,
                              other_is_giver ? other.visit->held_before : HeldObject{}});
          }
        }
        const MotionContext ctx{timelines[p.robot].heldAt(depart), objects.layoutAt(depart), parked};
        auto path = replan(p.robot, p.transit.front(), p.transit.back(), ctx);
        if (!path) continue;
        ++result.stats.replans;
        if (mode == 0) {
          p.transit = *path;
          p.transit_time = pathDuration(p.robot, *path);
        } else {
          p.staggered[mode] = *path;
          p.staggered_time[mode] = pathDuration(p.robot, *path);
        }
      }
    };
    // When each participant reaches its approach start (it then waits there and approaches so as to
    // arrive at T). Two robots arriving together can cross each other's way; staggering them (giver
    // first, or receiver first waiting back at its approach start) often clears it without delay.
    const int modes = parts.size() == 2 && params_.staggered_arrivals ? 3 : 1;
    auto arrivals = [&](int mode, double T) {
      auto travel = [&](int i) {
        return parts[i].staggered[mode].empty() ? parts[i].transit_time : parts[i].staggered_time[mode];
      };
      std::vector<double> at;
      for (const Participant& p : parts) at.push_back(T - p.approach_time);
      if (mode == 1) at[0] = at[1] - travel(1);  // giver in place before the receiver leaves
      if (mode == 2) {                           // receiver waits while the giver comes
        at[0] = at[1];
        at[1] = at[0] - travel(0);
      }
      return at;
    };
    while (!scheduled && T <= give_up) {
      std::optional<ScheduleConflict> round_conflict;
      // Modes 0-2: each participant on its own path (arriving together, giver first, receiver
      // first); mode 3: the composite path of ARC's subproblem, once there is one.
      for (int mode = 0; mode < 4 && !scheduled; ++mode) {
        if (deadline.expired()) return fail(k, "deadline");
        if (mode == 3 ? !composite : mode >= modes) continue;
        std::vector<RobotTimeline> trial = timelines;
        if (mode == 3) {
          const double depart = T - max_approach - composite_time;
          bool fits = true;
          for (int r : movers) fits = fits && depart >= timelines[r].end() - 1e-9;
          if (!fits) continue;
          for (std::size_t i = 0; i < movers.size(); ++i) {
            RobotTimeline& c = trial[movers[i]];
            c.append(depart, c.last());
            double t = depart;
            for (std::size_t w = 1; w < composite->size(); ++w) {
              t += composite_steps[w - 1];
              c.append(t, (*composite)[w][i]);
            }
          }
          for (const Participant& p : parts) {
            trial[p.robot].append(T - p.approach_time, p.visit->q_pre);
            trial[p.robot].append(T, p.visit->q);
          }
        } else {
          const std::vector<double> arrive = arrivals(mode, T);
          bool fits = true;
          for (std::size_t i = 0; i < parts.size(); ++i) {
            const double travel =
                parts[i].staggered[mode].empty() ? parts[i].transit_time : parts[i].staggered_time[mode];
            fits = fits && arrive[i] - travel >= timelines[parts[i].robot].end() - 1e-9;
          }
          if (!fits) continue;
          for (std::size_t i = 0; i < parts.size(); ++i) {
            const Participant& p = parts[i];
            RobotTimeline& c = trial[p.robot];
            const bool own = !p.staggered[mode].empty();
            const std::vector<JointVector>& path = own ? p.staggered[mode] : p.transit;
            const double depart = arrive[i] - (own ? p.staggered_time[mode] : p.transit_time);
            c.append(depart, c.last());  // wait where it stands: always clear (its standing was checked)
            appendPath(c, depart, path);
            c.append(T - p.approach_time, p.visit->q_pre);
            c.append(T, p.visit->q);
          }
        }
        // The transition itself at time T.
        const int o = a.object;
        if (a.type == TaskArcType::kPick) trial[a.robot].grasp(T, {o, tc.X_TO});
        if (a.type == TaskArcType::kPlace) trial[a.robot].release(T);
        if (a.type == TaskArcType::kHandover) {
          trial[a.robot].release(T);
          trial[a.robot2].grasp(T, {o, tc.X_TO2});
        }
        std::optional<ScheduleConflict> conflict;
        for (const int r : mode == 3 ? movers : std::vector<int>{}) {
          if (r == parts[0].robot || (parts.size() == 2 && r == parts[1].robot)) continue;
          conflict = checker_.check(trial[r], timelines[r].end(), kForever, trial, objects);
          if (conflict) break;
        }
        for (const Participant& p : parts) {
          if (conflict) break;
          conflict = checker_.check(trial[p.robot], timelines[p.robot].end(), kForever, trial, objects);
        }
        if (!conflict && a.type == TaskArcType::kPlace) conflict = checker_.checkResting(o, tc.X_WO, T, trial, a.robot);
        const bool with_partner =
            conflict && parts.size() == 2 && (conflict->other == parts[0].robot || conflict->other == parts[1].robot);
        // A conflict among the robots of this step (participants, and the movers of its composite
        // subproblem) is not one with a robot standing in the way.
        const bool internal =
            with_partner || (conflict && std::find(movers.begin(), movers.end(), conflict->other) != movers.end());
        if (with_partner && mode < 3 && !parts[0].staggered_tried[mode]) {
          parts[0].staggered_tried[mode] = true;
          replanTransits(mode);
          --mode;  // the same arrival mode again, with the new transits
          continue;
        }
        // Another robot standing still in the way (its schedule has ended) will not move before this
        // step is done: waiting cannot help, so move around it.
        if (conflict && conflict->other >= 0 && !internal && timelines[conflict->other].end() <= conflict->t &&
            std::find(blockers.begin(), blockers.end(), conflict->other) == blockers.end()) {
          blockers.push_back(conflict->other);
          replanTransits(0);
          for (int m = 1; m < 3; ++m)
            if (parts[0].staggered_tried[m]) replanTransits(m);
          --mode;
          continue;
        }
        // Moving around it did not help (gantries share one rail; an arm may stand right over the
        // spot): send the idle robot home first (ARC's subproblem with the blocker as a mover).
        if (params_.idle_arms_home && conflict && conflict->other >= 0 && !internal &&
            timelines[conflict->other].end() <= conflict->t &&
            std::find(evicted.begin(), evicted.end(), conflict->other) == evicted.end()) {
          evicted.push_back(conflict->other);
          if (sendHome(conflict->other)) {
            --mode;
            continue;
          }
        }
        // The composite path itself in conflict among its movers: the checker's time cuts sample the
        // motion at other instants than the planner did and found a graze. Plan it again.
        if (conflict && mode == 3 && internal && composite_tries < params_.composite_attempts && replanComposite()) {
          mode = 2;
          continue;
        }
        // Still in conflict with the partner or with a robot standing still: plan the robots involved
        // together (ARC), adding the robot in the way to the subproblem.
        const bool standing = conflict && conflict->other >= 0 && timelines[conflict->other].end() <= conflict->t;
        if (conflict && (standing || (with_partner && mode >= modes - 1)) && composite_tries < params_.composite_attempts) {
          const bool known = std::find(movers.begin(), movers.end(), conflict->other) != movers.end();
          if (!known && standing && static_cast<int>(movers.size()) < params_.max_composite_robots)
            movers.push_back(conflict->other);
          if ((!known || !composite) && replanComposite()) {
            mode = 2;  // try the composite path (mode 3) at this T
            continue;
          }
        }
        if (!conflict) {
          timelines = std::move(trial);
          // Robots that stepped aside continue from where they now stand.
          for (std::size_t i = parts.size(); mode == 3 && i < movers.size(); ++i)
            if (!fixNextTransit(movers[i])) return fail(k, "no path after " + scene.robots[movers[i]].id + " stepped aside");
          if (a.type == TaskArcType::kPick) objects.pick(o, T);
          if (a.type == TaskArcType::kPlace) objects.place(o, T, tc.X_WO);
          step_time[k] = T;
          scheduled = true;
          break;
        }
        round_conflict = conflict;
      }
      if (scheduled) break;
      const std::optional<ScheduleConflict> conflict = round_conflict;
      if (conflict) last_conflict = conflict;
      if (!conflict) {  // no mode fitted this T yet
        T += params_.delay_step;
        continue;
      }
      ++result.stats.delays;
      T += params_.delay_step;
    }
    if (!scheduled) {
      std::string what = "?";
      if (last_conflict) {
        const ScheduleConflict& c = *last_conflict;
        what = c.object >= 0 ? "object " + scene.objects[c.object].id
                             : (c.other >= 0 ? "robot " + scene.robots[c.other].id : std::string("an obstacle"));
        if (c.robot >= 0) what = scene.robots[c.robot].id + " against " + what;
      }
      return fail(k, "could not schedule step " + std::to_string(k) + " (" + describeStep(plan.steps[k], space) +
                         ") within " + std::to_string(static_cast<int>(params_.max_delay)) +
                         " s of delay; last conflict: " + what);
    }

    // Events: the receiver grasps at T and the giver lets go at the same instant (formats.md allows it).
    const std::string& actor_id = scene.robots[a.robot].id;
    switch (a.type) {
      case TaskArcType::kPick:
        events.push_back({PlanEvent::Type::kGrasp, T, actor_id, scene.objects[a.object].id, tc.X_TO, -1});
        break;
      case TaskArcType::kPlace:
        events.push_back({PlanEvent::Type::kRelease, T, actor_id, scene.objects[a.object].id, Pose::Identity(), -1});
        break;
      case TaskArcType::kHandover:
        events.push_back(
            {PlanEvent::Type::kGrasp, T, scene.robots[a.robot2].id, scene.objects[a.object].id, tc.X_TO2, -1});
        events.push_back({PlanEvent::Type::kRelease, T, actor_id, scene.objects[a.object].id, Pose::Identity(), -1});
        break;
      case TaskArcType::kInspect:
        events.push_back({PlanEvent::Type::kInspect, T, actor_id, "", Pose::Identity(), a.task});
        break;
      default:
        break;
    }

    // Retreats, giver first: each leaves after the gripper has closed or opened, as soon as it is clear.
    for (const Participant& p : parts) {
      const StepVisit& v = *p.visit;
      if ((v.q_post - v.q).cwiseAbs().maxCoeff() < 1e-12) continue;
      const double d = duration(p.robot, v.q, v.q_post);
      for (double rho = T + params_.dwell; rho <= T + params_.max_delay; rho += params_.delay_step) {
        RobotTimeline c = timelines[p.robot];
        c.append(rho, v.q);
        c.append(rho + d, v.q_post);
        if (!checker_.check(c, timelines[p.robot].end(), kForever, timelines, objects)) {
          timelines[p.robot] = std::move(c);
          break;
        }
        ++result.stats.delays;
      }
      // If no retreat was clear the robot stays at q (already checked) and leaves from there.
    }
    // The next visit's transit must start where this robot now stands.
    for (const Participant& p : parts)
      if (!fixNextTransit(p.robot)) return fail(k, "no path after a skipped retreat of " + scene.robots[p.robot].id);
    memo_.recordStep(plan.steps[k], tc, state);
  }

  // Home, when the scene wants every robot to end there.
  for (int r = 0; r < robots && scene.end_at_home; ++r) {
    std::vector<JointVector> path = motion.robots[r].home_path;
    if (path.empty() || (path.front() - timelines[r].last()).cwiseAbs().maxCoeff() > 1e-12) {
      const MotionContext ctx{{}, objects.layoutAt(timelines[r].end()), {}};
      auto p = replan(r, timelines[r].last(), scene.robots[r].home, ctx);
      if (!p) return fail(-1, "no path home for " + scene.robots[r].id);
      path = *p;
    }
    if (path.size() < 2) continue;
    bool done = false, replanned = false;
    for (double start = timelines[r].end(); start <= timelines[r].end() + params_.max_delay && !done;) {
      if (deadline.expired()) return fail(-1, "deadline");
      RobotTimeline c = timelines[r];
      appendPath(c, start, path);
      const auto conflict = checker_.check(c, timelines[r].end(), kForever, timelines, objects);
      if (!conflict) {
        timelines[r] = std::move(c);
        done = true;
        break;
      }
      if (conflict->other >= 0 && timelines[conflict->other].end() <= conflict->t && !replanned) {
        replanned = true;
        const MotionContext ctx{{}, objects.layoutAt(start), parkedAt(r, start)};
        if (auto p = replan(r, path.front(), path.back(), ctx)) {
          path = *p;
          ++result.stats.replans;
          continue;
        }
      }
      ++result.stats.delays;
      start += params_.delay_step;
    }
    if (!done) return fail(-1, "could not bring " + scene.robots[r].id + " home without collisions");
  }

  memo_.recordEnd(state);
  Plan& out = result.plan;
  for (int r = 0; r < robots; ++r) {
    RobotTrajectory traj;
    traj.robot = scene.robots[r].id;
    traj.joint_names = scene.robots[r].model->joint_names;
    for (const TimedPoint& p : timelines[r].points()) traj.points.push_back({p.t, p.q});
    out.robots.push_back(std::move(traj));
  }
  std::stable_sort(events.begin(), events.end(), [](const PlanEvent& x, const PlanEvent& y) { return x.t < y.t; });
  out.events = std::move(events);
  out.scene = scene.name;
  out.makespan = out.lastTime();
  result.ok = true;
  result.step_times = step_time;
  result.stats.checks = static_cast<std::int64_t>(context_->counters().configuration_checks - checks_before);
  return result;
}

}  // namespace dash
