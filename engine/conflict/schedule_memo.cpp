#include "engine/conflict/schedule_memo.h"

#include <algorithm>

#include "engine/core/check.h"

namespace dash {

namespace {

bool same(const JointVector& a, const JointVector& b) { return a.size() == b.size() && a == b; }
bool same(const Pose& a, const Pose& b) { return a.matrix() == b.matrix(); }

bool same(const TransitionConfig& a, const TransitionConfig& b) {
  return a.sampled == b.sampled && same(a.q, b.q) && same(a.q2, b.q2) && same(a.X_WO, b.X_WO) &&
         same(a.X_TO, b.X_TO) && same(a.X_TO2, b.X_TO2);
}

}  // namespace

int ScheduleMemo::resume(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                         ScheduleState& state) const {
  if (!last_) return 0;
  const int limit = std::min({static_cast<int>(keys_.size()), static_cast<int>(plan.steps.size()),
                              static_cast<int>(transitions.size())});
  int shared = 0;
  for (; shared < limit; ++shared) {
    const StepKey& old = keys_[shared];
    const TaskStep& now = plan.steps[shared];
    if (!(old.action == now.action) || old.after != now.after || !same(old.transition, transitions[shared])) break;
  }
  if (shared == 0) return 0;
  const StepMark& mark = marks_[shared - 1];
  std::vector<double> step_time = std::move(state.step_time);
  state = *last_;
  DASH_DEMAND(state.timelines.size() == mark.robots.size());
  for (std::size_t r = 0; r < state.timelines.size(); ++r) state.timelines[r].rewind(mark.robots[r]);
  state.objects.rewind(mark.objects);
  state.events.resize(mark.events);
  std::copy_n(last_->step_time.begin(), shared, step_time.begin());
  state.step_time = std::move(step_time);
  return shared;
}

void ScheduleMemo::restart(int steps) {
  DASH_DEMAND(steps >= 0 && steps <= this->steps());
  keys_.resize(static_cast<std::size_t>(steps));
  marks_.resize(static_cast<std::size_t>(steps));
}

void ScheduleMemo::forgetFrom(double t) {
  if (!last_) return;
  int keep = 0;
  for (; keep < steps(); ++keep) {
    const StepMark& mark = marks_[keep];
    bool before = true;
    for (std::size_t r = 0; r < mark.robots.size() && before; ++r)
      before = last_->timelines[r].points()[mark.robots[r].points - 1].t < t;
    if (!before) break;
  }
  restart(keep);
}

void ScheduleMemo::recordStep(const TaskStep& step, const TransitionConfig& transition, const ScheduleState& state) {
  keys_.push_back({step.action, step.after, transition});
  StepMark mark;
  for (const RobotTimeline& t : state.timelines) mark.robots.push_back(t.mark());
  mark.objects = state.objects.mark();
  mark.events = state.events.size();
  marks_.push_back(std::move(mark));
}

}  // namespace dash
