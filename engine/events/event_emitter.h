#pragma once
// What a planner holds to emit events: the injected sink, the run's clock and the current
// iteration. One emitter per run; the planner passes it (by reference) to its layers.
//
// An emitter without a sink (nullptr) drops everything after one branch, so planners can emit
// unconditionally. The emitter itself is not thread safe (the iteration and the phase totals are
// plain members): threads that emit in parallel each use their own emitter over the same sink.
#include <algorithm>
#include <array>
#include <iterator>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "engine/core/stopwatch.h"
#include "engine/events/events.h"

namespace dash::log {

/// Seconds spent in each phase, indexed by Phase.
using PhaseTotals = std::array<double, kPhaseCount>;

/// A run's total time: the sum of its phases (phases are exclusive, so no second counts twice).
inline double phaseSum(const PhaseTotals& totals) {
  double sum = 0.0;
  for (double t : totals) sum += t;
  return sum;
}

class EventEmitter {
 public:
  /// `sink` may be nullptr (emit nothing); it must outlive the emitter. The run's clock starts now.
  explicit EventEmitter(EventSink* sink) : sink_(sink) {}

  bool enabled() const { return sink_ != nullptr; }
  double now() const { return clock_.seconds(); }
  int iteration() const { return iteration_; }
  void setIteration(int iteration) { iteration_ = iteration; }

  void emit(EventPayload payload) {
    if (sink_ != nullptr) sink_->onEvent(Event{clock_.seconds(), iteration_, std::move(payload)});
  }

  void vertex(Layer layer, std::uint32_t id, std::string label = {}) {
    if (sink_ == nullptr) return;
    emit(RepresentationEvent{.layer = layer, .kind = ElementKind::Vertex, .id = id, .label = std::move(label)});
  }
  /// hyperarc() with head and tail as ranges of typed ids (anything with value(): VertexId,
  /// ExtendedVertexId), converted only when a sink listens.
  template <class HeadIds, class TailIds>
  void hyperarcOf(Layer layer, std::string type, std::uint32_t id, const HeadIds& head, const TailIds& tail) {
    if (sink_ == nullptr) return;
    hyperarc(layer, std::move(type), id, idValues(head), idValues(tail));
  }
  template <class Ids>
  static std::vector<std::uint32_t> idValues(const Ids& ids) {
    std::vector<std::uint32_t> out;
    for (const auto& v : ids) out.push_back(static_cast<std::uint32_t>(v.value()));
    return out;
  }
  void hyperarc(Layer layer, std::string type, std::uint32_t id, std::vector<std::uint32_t> head,
                std::vector<std::uint32_t> tail, std::string label = {}) {
    if (sink_ == nullptr) return;
    emit(RepresentationEvent{.layer = layer, .kind = ElementKind::Hyperarc, .arc_type = std::move(type),
                             .id = id, .head = std::move(head), .tail = std::move(tail),
                             .label = std::move(label)});
  }
  void removed(Layer layer, ElementKind kind, std::uint32_t id) {
    if (sink_ == nullptr) return;
    emit(RepresentationEvent{.layer = layer, .kind = kind, .change = ElementChange::Removed, .id = id});
  }
  void constraint(ConstraintKind kind, ConstraintAction action, std::uint32_t id, std::string content,
                  std::vector<std::uint32_t> vertices, std::string conflict = {}) {
    if (sink_ == nullptr) return;
    emit(ConstraintEvent{kind, action, id, std::move(content), std::move(vertices), std::move(conflict)});
  }
  void taskSpaceExpansion(std::uint32_t object_id, std::string object_label, std::string added,
                          std::string reason) {
    if (sink_ == nullptr) return;
    emit(TaskSpaceExpansionEvent{object_id, std::move(object_label), std::move(added), std::move(reason)});
  }
  void counter(std::string name, std::int64_t value) {
    if (sink_ == nullptr) return;
    emit(CounterEvent{std::move(name), value});
  }
  void progress(Phase phase, std::int64_t done, std::int64_t total, double rate, std::string current) {
    if (sink_ == nullptr) return;
    emit(ProgressEvent{phase, done, total, rate, std::move(current)});
  }

  /// Low-level phase boundaries (PhaseTimer is the usual way). Phases are exclusive: a phase begun
  /// while another is open pauses it (its interval so far is ended and booked) and the enclosing
  /// phase resumes when the inner one ends, so the totals add up to at most the wall time and no
  /// second is booked twice. beginPhase returns the start time; endPhase books the last interval of
  /// `phase` and returns its length.
  double beginPhase(Phase phase) {
    const double t = clock_.seconds();
    if (!open_.empty()) closeInterval(open_.back(), t);
    open_.push_back({phase, t});
    if (sink_ != nullptr) sink_->onEvent(Event{t, iteration_, PhaseEvent{phase, PhaseBoundary::Start, 0.0}});
    return t;
  }
  double endPhase(Phase phase, double /*start_t*/) {
    const double t = clock_.seconds();
    // The innermost open interval of `phase` (normally the top: PhaseTimers nest).
    auto it = std::find_if(open_.rbegin(), open_.rend(), [&](const OpenPhase& o) { return o.phase == phase; });
    if (it == open_.rend()) return 0.0;
    const bool top = it == open_.rbegin();
    const double duration = closeInterval(*it, t);
    open_.erase(std::next(it).base());
    if (top && !open_.empty()) {
      open_.back().start = t;
      if (sink_ != nullptr) sink_->onEvent(Event{t, iteration_, PhaseEvent{open_.back().phase, PhaseBoundary::Start, 0.0}});
    }
    return duration;
  }
  /// Books `seconds` of the innermost open phase's current interval to `phase` instead (work
  /// interleaved too finely for PhaseTimer: Lazy-PRM's roadmap growth between its lazy collision
  /// checks). At most the interval's length so far; nothing when no phase is open.
  void rebook(Phase phase, double seconds) {
    if (open_.empty() || !(seconds > 0.0)) return;
    OpenPhase& top = open_.back();
    const double t = clock_.seconds();
    seconds = std::min(seconds, t - top.start);
    if (top.phase == phase) return;
    top.start += seconds;
    totals_[static_cast<int>(phase)] += seconds;
    if (sink_ != nullptr) sink_->onEvent(Event{t, iteration_, PhaseEvent{phase, PhaseBoundary::End, seconds}});
  }

  const PhaseTotals& phaseTotals() const { return totals_; }
  /// Whether `phase` is the innermost open phase (the one being booked now).
  bool inPhase(Phase phase) const { return !open_.empty() && open_.back().phase == phase; }

 private:
  struct OpenPhase {
    Phase phase;
    double start;  ///< of its current (unpaused) interval
  };
  /// Ends `o`'s current interval at t: booked to the totals and emitted. Returns its length.
  double closeInterval(const OpenPhase& o, double t) {
    const double duration = t - o.start;
    totals_[static_cast<int>(o.phase)] += duration;
    if (sink_ != nullptr) sink_->onEvent(Event{t, iteration_, PhaseEvent{o.phase, PhaseBoundary::End, duration}});
    return duration;
  }

  EventSink* sink_;
  Stopwatch clock_;
  int iteration_ = 0;
  PhaseTotals totals_{};
  std::vector<OpenPhase> open_;  ///< innermost last
};

/// RAII phase interval: emits Start now and End when it goes out of scope (or at stop()), and
/// accumulates the interval into the emitter's phase totals.
class PhaseTimer {
 public:
  PhaseTimer(EventEmitter& emitter, Phase phase)
      : emitter_(&emitter), phase_(phase), start_(emitter.beginPhase(phase)) {}
  ~PhaseTimer() { stop(); }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

  /// Ends the interval early; returns its length (0 if already stopped).
  double stop() {
    if (emitter_ == nullptr) return 0.0;
    const double d = emitter_->endPhase(phase_, start_);
    emitter_ = nullptr;
    return d;
  }

 private:
  EventEmitter* emitter_;
  Phase phase_;
  double start_;
};

}  // namespace dash::log
