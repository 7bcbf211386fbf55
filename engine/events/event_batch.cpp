#include "engine/events/event_batch.h"

#include <cstring>

namespace dash::log {
namespace {

constexpr std::size_t kHeaderBytes = 1 + 8 + 4;  // type, t, iteration

std::size_t textBytes(std::string_view s) { return 4 + s.size(); }
std::size_t idBytes(const std::vector<std::uint32_t>& ids) { return 4 + 4 * ids.size(); }

/// Writes fields at a cursor inside room already made.
class Cursor {
 public:
  explicit Cursor(unsigned char* p) : p_(p) {}
  template <class T>
  Cursor& put(T v) {
    std::memcpy(p_, &v, sizeof v);
    p_ += sizeof v;
    return *this;
  }
  Cursor& text(std::string_view s) {
    put(static_cast<std::uint32_t>(s.size()));
    if (!s.empty()) std::memcpy(p_, s.data(), s.size());
    p_ += s.size();
    return *this;
  }
  Cursor& ids(const std::vector<std::uint32_t>& v) {
    put(static_cast<std::uint32_t>(v.size()));
    if (!v.empty()) std::memcpy(p_, v.data(), 4 * v.size());
    p_ += 4 * v.size();
    return *this;
  }

 private:
  unsigned char* p_;
};

}  // namespace

void EventBatch::reserve(std::size_t capacity) {
  if (capacity <= capacity_) return;
  std::unique_ptr<unsigned char[]> bigger(new unsigned char[capacity]);
  if (size_ > 0) std::memcpy(bigger.get(), data_.get(), size_);
  data_ = std::move(bigger);
  capacity_ = capacity;
}

void EventBatch::append(const Event& event) {
  const EventPayload& p = event.payload;
  std::size_t n = kHeaderBytes;
  if (const auto* r = std::get_if<RepresentationEvent>(&p)) {
    n += 3 + 4 + textBytes(r->arc_type) + textBytes(r->label) + idBytes(r->head) + idBytes(r->tail);
    Cursor c(grow(n));
    c.put(static_cast<std::uint8_t>(0)).put(event.t).put(static_cast<std::int32_t>(event.iteration));
    c.put(static_cast<std::uint8_t>(r->layer)).put(static_cast<std::uint8_t>(r->kind));
    c.put(static_cast<std::uint8_t>(r->change)).put(r->id).text(r->arc_type).text(r->label).ids(r->head).ids(r->tail);
  } else if (const auto* k = std::get_if<ConstraintEvent>(&p)) {
    n += 2 + 4 + textBytes(k->content) + idBytes(k->vertices) + textBytes(k->conflict);
    Cursor c(grow(n));
    c.put(static_cast<std::uint8_t>(1)).put(event.t).put(static_cast<std::int32_t>(event.iteration));
    c.put(static_cast<std::uint8_t>(k->kind)).put(static_cast<std::uint8_t>(k->action)).put(k->id);
    c.text(k->content).ids(k->vertices).text(k->conflict);
  } else if (const auto* x = std::get_if<TaskSpaceExpansionEvent>(&p)) {
    n += 4 + textBytes(x->object_label) + textBytes(x->added) + textBytes(x->reason);
    Cursor c(grow(n));
    c.put(static_cast<std::uint8_t>(2)).put(event.t).put(static_cast<std::int32_t>(event.iteration));
    c.put(x->object_id).text(x->object_label).text(x->added).text(x->reason);
  } else if (const auto* ph = std::get_if<PhaseEvent>(&p)) {
    n += 2 + 8;
    Cursor c(grow(n));
    c.put(static_cast<std::uint8_t>(3)).put(event.t).put(static_cast<std::int32_t>(event.iteration));
    c.put(static_cast<std::uint8_t>(ph->phase)).put(static_cast<std::uint8_t>(ph->boundary)).put(ph->duration);
  } else if (const auto* g = std::get_if<ProgressEvent>(&p)) {
    n += 1 + 8 + 8 + 8 + textBytes(g->current);
    Cursor c(grow(n));
    c.put(static_cast<std::uint8_t>(5)).put(event.t).put(static_cast<std::int32_t>(event.iteration));
    c.put(static_cast<std::uint8_t>(g->phase)).put(g->done).put(g->total).put(g->rate).text(g->current);
  } else {
    const auto& counter = std::get<CounterEvent>(p);
    n += textBytes(counter.name) + 8;
    Cursor c(grow(n));
    c.put(static_cast<std::uint8_t>(4)).put(event.t).put(static_cast<std::int32_t>(event.iteration));
    c.text(counter.name).put(counter.value);
  }
  ++events_;
}

std::string_view EventBatch::Reader::text() {
  const auto size = read<std::uint32_t>();
  const std::string_view s(reinterpret_cast<const char*>(p_), size);
  p_ += size;
  return s;
}

IdView EventBatch::Reader::ids() {
  const auto size = read<std::uint32_t>();
  const IdView v(p_, size);
  p_ += 4 * static_cast<std::size_t>(size);
  return v;
}

bool EventBatch::Reader::next(EventView& e) {
  if (p_ >= end_) return false;
  e.type = read<std::uint8_t>();
  e.t = read<double>();
  e.iteration = read<std::int32_t>();
  switch (e.type) {
    case 0:
      e.layer = static_cast<Layer>(read<std::uint8_t>());
      e.kind = static_cast<ElementKind>(read<std::uint8_t>());
      e.change = static_cast<ElementChange>(read<std::uint8_t>());
      e.id = read<std::uint32_t>();
      e.arc_type = text();
      e.label = text();
      e.head = ids();
      e.tail = ids();
      break;
    case 1:
      e.constraint_kind = static_cast<ConstraintKind>(read<std::uint8_t>());
      e.action = static_cast<ConstraintAction>(read<std::uint8_t>());
      e.id = read<std::uint32_t>();
      e.content = text();
      e.vertices = ids();
      e.conflict = text();
      break;
    case 2:
      e.id = read<std::uint32_t>();
      e.object_label = text();
      e.added = text();
      e.reason = text();
      break;
    case 3:
      e.phase = static_cast<Phase>(read<std::uint8_t>());
      e.boundary = static_cast<PhaseBoundary>(read<std::uint8_t>());
      e.duration = read<double>();
      break;
    case 5:
      e.phase = static_cast<Phase>(read<std::uint8_t>());
      e.done = read<std::int64_t>();
      e.total = read<std::int64_t>();
      e.rate = read<double>();
      e.current = text();
      break;
    default:
      e.name = text();
      e.value = read<std::int64_t>();
      break;
  }
  return true;
}

}  // namespace dash::log
