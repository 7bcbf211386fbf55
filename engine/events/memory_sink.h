#pragma once
// Keeps every event in memory: for tests, and for callers that want a run's events after the fact.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "engine/events/events.h"

namespace dash::log {

class MemorySink final : public EventSink {
 public:
  void onEvent(const Event& event) override;

  /// A copy of everything received so far, in arrival order.
  std::vector<Event> events() const;
  std::size_t size() const;
  void clear();

  /// Net element count of a layer (added minus removed): the representation's size.
  std::int64_t count(Layer layer, ElementKind kind) const;
  /// Hyperarcs of one type added to a layer ("pick", "handover", ...).
  std::int64_t countHyperarcs(Layer layer, const std::string& arc_type) const;
  std::int64_t countConstraints(ConstraintKind kind, ConstraintAction action) const;
  std::int64_t countTaskSpaceExpansions() const;
  /// The latest value of a counter, or `fallback` if it was never emitted.
  std::int64_t counter(const std::string& name, std::int64_t fallback = 0) const;
  /// Seconds in a phase, summed over its End events.
  double phaseSeconds(Phase phase) const;

 private:
  mutable std::mutex mutex_;
  std::vector<Event> events_;
};

}  // namespace dash::log
