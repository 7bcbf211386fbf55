#include "engine/events/memory_sink.h"

namespace dash::log {

void MemorySink::onEvent(const Event& event) {
  std::lock_guard lock(mutex_);
  events_.push_back(event);
}

std::vector<Event> MemorySink::events() const {
  std::lock_guard lock(mutex_);
  return events_;
}

std::size_t MemorySink::size() const {
  std::lock_guard lock(mutex_);
  return events_.size();
}

void MemorySink::clear() {
  std::lock_guard lock(mutex_);
  events_.clear();
}

std::int64_t MemorySink::count(Layer layer, ElementKind kind) const {
  std::lock_guard lock(mutex_);
  std::int64_t n = 0;
  for (const Event& e : events_) {
    if (const auto* r = std::get_if<RepresentationEvent>(&e.payload); r && r->layer == layer && r->kind == kind) {
      n += r->change == ElementChange::Added ? 1 : -1;
    }
  }
  return n;
}

std::int64_t MemorySink::countHyperarcs(Layer layer, const std::string& arc_type) const {
  std::lock_guard lock(mutex_);
  std::int64_t n = 0;
  for (const Event& e : events_) {
    const auto* r = std::get_if<RepresentationEvent>(&e.payload);
    if (r && r->layer == layer && r->kind == ElementKind::Hyperarc && r->change == ElementChange::Added &&
        r->arc_type == arc_type) {
      ++n;
    }
  }
  return n;
}

std::int64_t MemorySink::countConstraints(ConstraintKind kind, ConstraintAction action) const {
  std::lock_guard lock(mutex_);
  std::int64_t n = 0;
  for (const Event& e : events_) {
    const auto* c = std::get_if<ConstraintEvent>(&e.payload);
    if (c && c->kind == kind && c->action == action) ++n;
  }
  return n;
}

std::int64_t MemorySink::countTaskSpaceExpansions() const {
  std::lock_guard lock(mutex_);
  std::int64_t n = 0;
  for (const Event& e : events_) n += std::holds_alternative<TaskSpaceExpansionEvent>(e.payload) ? 1 : 0;
  return n;
}

std::int64_t MemorySink::counter(const std::string& name, std::int64_t fallback) const {
  std::lock_guard lock(mutex_);
  std::int64_t value = fallback;
  for (const Event& e : events_) {
    if (const auto* c = std::get_if<CounterEvent>(&e.payload); c && c->name == name) value = c->value;
  }
  return value;
}

double MemorySink::phaseSeconds(Phase phase) const {
  std::lock_guard lock(mutex_);
  double total = 0.0;
  for (const Event& e : events_) {
    const auto* p = std::get_if<PhaseEvent>(&e.payload);
    if (p && p->phase == phase && p->boundary == PhaseBoundary::End) total += p->duration;
  }
  return total;
}

}  // namespace dash::log
