#pragma once
// A batch of events in one flat byte buffer: what a SqliteRecorder fills on the planner's thread and
// the ResultsDb's writer thread reads back. Appending an event copies its fields into the buffer
// (no allocation per event: the buffer grows by doubling, and a batch is handed over whole); reading
// gives views into the buffer, so the writer binds the strings to SQLite without copying them again.
//
// Layout per event (host byte order; the buffer never leaves the process): type (the payload's
// variant index, 1 byte), t (8), iteration (4), then the payload's fields in declaration order;
// strings as a 4-byte length and their bytes, id lists as a 4-byte count and 4 bytes per id.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string_view>
#include <vector>

#include "engine/events/events.h"

namespace dash::log {

/// A list of ids inside a batch (possibly unaligned).
class IdView {
 public:
  IdView() = default;
  IdView(const unsigned char* data, std::uint32_t size) : data_(data), size_(size) {}
  std::uint32_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  std::uint32_t operator[](std::uint32_t i) const {
    std::uint32_t v;
    std::memcpy(&v, data_ + 4 * static_cast<std::size_t>(i), sizeof v);
    return v;
  }

 private:
  const unsigned char* data_ = nullptr;
  std::uint32_t size_ = 0;
};

/// One event read back from a batch: the header, the payload type, and that type's fields (the
/// other fields keep their defaults). Views point into the batch.
struct EventView {
  double t = 0.0;
  int iteration = 0;
  std::size_t type = 0;  ///< EventPayload's index: 0 representation, 1 constraint, 2 task space expansion, 3 phase,
                         ///< 4 counter, 5 progress

  // Representation (type 0).
  Layer layer = Layer::Task;
  ElementKind kind = ElementKind::Vertex;
  ElementChange change = ElementChange::Added;
  std::string_view arc_type, label;
  IdView head, tail;
  std::uint32_t id = 0;  ///< element, constraint or object id

  // Constraint (type 1).
  ConstraintKind constraint_kind = ConstraintKind::Frontier;
  ConstraintAction action = ConstraintAction::Created;
  std::string_view content, conflict;
  IdView vertices;

  // Task space expansion (type 2): id is the object's.
  std::string_view object_label, added, reason;

  // Phase (type 3), and progress's phase (type 5).
  Phase phase = Phase::Other;
  PhaseBoundary boundary = PhaseBoundary::Start;
  double duration = 0.0;

  // Counter (type 4).
  std::string_view name;
  std::int64_t value = 0;

  // Progress (type 5), with `phase`.
  std::int64_t done = 0, total = 0;
  double rate = 0.0;
  std::string_view current;
};

class EventBatch {
 public:
  explicit EventBatch(std::size_t reserve_bytes = 0) { reserve(reserve_bytes); }

  void append(const Event& event);
  std::size_t events() const { return events_; }
  std::size_t bytes() const { return size_; }
  bool empty() const { return events_ == 0; }

  /// Reads the events in order: `while (reader.next(view)) ...`.
  class Reader {
   public:
    explicit Reader(const EventBatch& batch) : p_(batch.data_.get()), end_(p_ + batch.size_) {}
    bool next(EventView& out);

   private:
    template <class T>
    T read() {
      T v;
      std::memcpy(&v, p_, sizeof v);
      p_ += sizeof v;
      return v;
    }
    std::string_view text();
    IdView ids();

    const unsigned char* p_;
    const unsigned char* end_;
  };

 private:
  void reserve(std::size_t capacity);
  /// Room for `n` more bytes (doubling the capacity as needed); returns where they start.
  unsigned char* grow(std::size_t n) {
    if (size_ + n > capacity_) reserve(std::max(2 * capacity_, size_ + n));
    unsigned char* at = data_.get() + size_;
    size_ += n;
    return at;
  }

  // A plain array, not a std::vector: growing must not zero the bytes it is about to overwrite.
  std::unique_ptr<unsigned char[]> data_;
  std::size_t size_ = 0, capacity_ = 0;
  std::size_t events_ = 0;
};

}  // namespace dash::log
