#include "engine/conflict/scheduler.h"

#include <algorithm>
#include <cmath>

#include "engine/conflict/step_scheduler.h"
#include "engine/core/stopwatch.h"

namespace dash {

namespace {

ObjectLayout startLayout(const TaskSpace& space) {
  ObjectLayout layout = ObjectLayout::atStart(space.scene());
  for (int o = 0; o < space.objectCount(); ++o) layout.place(o, space.location(o, space.startLocation(o)).X_WO);
  return layout;
}

/// One build's progress for people (events.h ProgressEvent), rate-limited by wall time. It reads the
/// clock and emits; it never changes what the build does.
class BuildProgress {
 public:
  BuildProgress(log::EventEmitter* emitter, double interval, const TaskPlan& plan, const Scene& scene)
      : emitter_(emitter != nullptr && emitter->enabled() ? emitter : nullptr), interval_(interval), plan_(plan),
        scene_(scene) {}

  /// The build starts at step `first` (the steps before it taken from the last schedule).
  void start(int first) {
    first_ = first;
    if (emitter_ != nullptr) emit(first, robotsOf(first));
  }
  /// Step k is about to be scheduled.
  void before(int k) {
    if (emitter_ != nullptr && watch_.seconds() - last_ >= interval_) emit(k, robotsOf(k));
  }
  /// Every step scheduled; the robots go home.
  void home() {
    if (emitter_ != nullptr && watch_.seconds() - last_ >= interval_) emit(total(), "robots home");
  }
  /// The build ended with `done` steps scheduled.
  void end(int done) {
    if (emitter_ != nullptr) emit(done, "");
  }

 private:
  int total() const { return static_cast<int>(plan_.steps.size()); }
  std::string robotsOf(int k) const {
    if (k < 0 || k >= total()) return "robots home";
    const TaskArc& a = plan_.steps[static_cast<std::size_t>(k)].action;
    std::string out = scene_.robots[static_cast<std::size_t>(a.robot)].id;
    if (a.type == TaskArcType::kHandover) out += ", " + scene_.robots[static_cast<std::size_t>(a.robot2)].id;
    return out;
  }
  void emit(int done, std::string current) {
    const double seconds = watch_.seconds();
    last_ = seconds;
    const double rate = seconds > 0.0 ? std::max(0, done - first_) / seconds : 0.0;
    emitter_->progress(log::Phase::ConflictResolution, done, total(), rate, std::move(current));
  }

  log::EventEmitter* emitter_;
  double interval_;
  const TaskPlan& plan_;
  const Scene& scene_;
  Stopwatch watch_;
  double last_ = 0.0;
  int first_ = 0;
};

}  // namespace

void applySchedulerParameters(SchedulerParams& params, const ParamValues& values) {
  const std::pair<const char*, bool*> flags[] = {{"staggered_arrivals", &params.staggered_arrivals},
                                                 {"idle_arms_home", &params.idle_arms_home},
                                                 {"parking", &params.parking},
                                                 {"schedule_memo", &params.schedule_memo},
                                                 {"conflict_replanning", &params.conflict_replanning}};
  for (const auto& [name, field] : flags)
    if (values.contains(name)) *field = paramBool(values, name);
  if (values.contains("validation_threads")) params.threads = paramInt(values, "validation_threads");
}

Scheduler::Scheduler(const CollisionWorld& world, CollisionContext& context, SchedulerParams params)
    : world_(&world), context_(&context), params_(params), checker_(world, context, params.threads) {}

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

double clearOfWindows(const std::vector<StepWindow>& windows, int robot, int step, double from, double duration) {
  double s = from;
  for (bool moved = true; moved && std::isfinite(s);) {
    moved = false;
    for (const StepWindow& w : windows)
      if (w.robot == robot && w.step == step && s < w.t1 && s + duration > w.t0) {
        s = w.t1;
        moved = true;
      }
  }
  return s;
}

ScheduleResult Scheduler::build(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                MotionLayerResult motion, const TaskSpace& space, const MoveReplanner& replan,
                                const Deadline& deadline) {
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  ScheduleResult result;
  ScheduleState state{{}, ObjectTimeline(startLayout(space)), {}, std::vector<double>(plan.steps.size(), 0.0)};
  for (int r = 0; r < robots; ++r) state.timelines.emplace_back(r, scene.robots[r].home);
  ScheduleBuild b{*this, checker_, params_, scene, state, motion, std::vector<std::size_t>(static_cast<std::size_t>(robots), 0),
                  replan, deadline, result.stats, plan, constraints_, windows_};
  const std::uint64_t checks_before = context_->counters().configuration_checks;
  BuildProgress progress(progress_emitter_, progress_interval_, plan, scene);
  auto fail = [&](int step, std::string why) {
    progress.end(step >= 0 ? step : static_cast<int>(plan.steps.size()));
    memo_.recordEnd(state);
    result.ok = false;
    result.failed_step = step;
    result.reason = std::move(why);
    result.stats.checks = static_cast<std::int64_t>(context_->counters().configuration_checks - checks_before);
    return result;
  };

  // The steps this plan shares with the last one built are taken as they were scheduled then.
  const int shared = params_.schedule_memo ? memo_.resume(plan, transitions, state) : 0;
  memo_.restart(shared);
  result.stats.reused_steps = shared;
  progress.start(shared);
  for (int k = 0; k < shared; ++k) {
    const TaskArc& a = plan.steps[k].action;
    ++b.next_visit[a.robot];
    if (a.type == TaskArcType::kHandover) ++b.next_visit[a.robot2];
  }
  for (int r = 0; r < robots && shared > 0; ++r)
    if (!b.fixNextTransit(r)) return fail(shared, "no path for " + scene.robots[r].id + " on from the shared steps");

  // Each step in the task plan's order: placed at the earliest time its dependencies and robots allow.
  for (int k = shared; k < static_cast<int>(plan.steps.size()); ++k) {
    progress.before(k);
    StepScheduler step(b, plan, k, transitions[k], space);
    if (auto why = step.place()) {
      if (step.lastConflict())
        result.region = conflictRegion(*world_, *context_, state, plan, k, transitions, *step.lastConflict(),
                                       {step.lastConflictRobot(), step.lastConflictOther()}, params_.delay_step);
      return fail(k, std::move(*why));
    }
    std::string why;
    if (!step.finish(why)) return fail(k, std::move(why));
    memo_.recordStep(plan.steps[k], transitions[k], state);
  }
  progress.home();
  if (auto why = bringHome(b)) return fail(-1, std::move(*why));

  progress.end(static_cast<int>(plan.steps.size()));
  memo_.recordEnd(state);
  result.plan = toPlan(scene, state);
  result.ok = true;
  result.step_times = state.step_time;
  result.stats.checks = static_cast<std::int64_t>(context_->counters().configuration_checks - checks_before);
  return result;
}

std::optional<std::string> Scheduler::bringHome(ScheduleBuild& b) const {
  const Scene& scene = b.scene;
  std::vector<RobotTimeline>& timelines = b.state.timelines;
  for (int r = 0; r < static_cast<int>(scene.robots.size()) && scene.end_at_home; ++r) {
    std::vector<JointVector> path = b.motion.robots[r].home_path;
    if (path.empty() || (path.front() - timelines[r].last()).cwiseAbs().maxCoeff() > 1e-12) {
      const MotionContext ctx{{}, b.state.objects.layoutAt(timelines[r].end()), {}};
      auto p = b.replan(r, timelines[r].last(), scene.robots[r].home, ctx);
      if (!p) return "no path home for " + scene.robots[r].id;
      path = *p;
    }
    if (path.size() < 2) continue;
    bool done = false, replanned = false;
    double give_up = timelines[r].end() + params_.max_delay;
    for (double start = timelines[r].end(); start <= give_up && !done;) {
      if (b.deadline.expired()) return std::string("deadline");
      if (const double clear = b.clearFrom(r, -1, start, pathDuration(r, path)); clear > start) {
        if (!std::isfinite(clear)) break;  // a clock-time window to the end of the plan (StepWindow)
        give_up = std::max(give_up, clear + params_.max_delay);
        start = clear;
        continue;
      }
      RobotTimeline c = timelines[r];
      appendPath(c, start, path);
      const auto conflict = b.checker.check(c, timelines[r].end(), kForever, timelines, b.state.objects);
      if (!conflict) {
        timelines[r] = std::move(c);
        done = true;
        break;
      }
      if (params_.conflict_replanning && conflict->other >= 0 && timelines[conflict->other].end() <= conflict->t &&
          !replanned) {
        replanned = true;
        const MotionContext ctx{{}, b.state.objects.layoutAt(start), b.parkedAt(r, start)};
        if (auto p = b.replan(r, path.front(), path.back(), ctx)) {
          path = *p;
          ++b.stats.replans;
          continue;
        }
      }
      ++b.stats.delays;
      start += params_.delay_step;
    }
    if (!done) return "could not bring " + scene.robots[r].id + " home without collisions";
  }
  return std::nullopt;
}

Plan Scheduler::toPlan(const Scene& scene, ScheduleState& state) {
  Plan out;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r) {
    RobotTrajectory traj;
    traj.robot = scene.robots[r].id;
    traj.joint_names = scene.robots[r].model->joint_names;
    for (const TimedPoint& p : state.timelines[r].points()) traj.points.push_back({p.t, p.q});
    out.robots.push_back(std::move(traj));
  }
  std::vector<PlanEvent> events = std::move(state.events);
  std::stable_sort(events.begin(), events.end(), [](const PlanEvent& x, const PlanEvent& y) { return x.t < y.t; });
  out.events = std::move(events);
  out.scene = scene.name;
  out.makespan = out.lastTime();
  return out;
}

}  // namespace dash
