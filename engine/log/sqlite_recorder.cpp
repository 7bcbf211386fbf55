#include "engine/log/sqlite_recorder.h"

#include "engine/log/results_db_impl.h"

namespace dash::log {
namespace {

// Bytes to reserve for a batch: a representation event with a short label and a few ids takes
// about 50 (the buffer doubles if a batch needs more).
std::size_t batchReserve(const DbOptions& options) { return static_cast<std::size_t>(options.batch_events) * 64; }

// A batch is also handed over at this size, whatever its event count (long labels or id lists).
constexpr std::size_t kMaxBatchBytes = 8u << 20;

}  // namespace

SqliteRecorder::SqliteRecorder(ResultsDb::Impl& db, std::string uuid, std::int64_t run_id)
    : db_(&db), uuid_(std::move(uuid)), run_id_(run_id), pending_(batchReserve(db.options)) {}

SqliteRecorder::~SqliteRecorder() {
  handOver(true);
  std::lock_guard lock(mutex_);
  if (db_ == nullptr) return;  // the database went first
  std::lock_guard db_lock(db_->mutex);
  if (auto it = db_->active.find(uuid_); it != db_->active.end() && it->second.recorder == this) {
    it->second.recorder = nullptr;
  }
}

std::int64_t SqliteRecorder::acceptedEvents() const {
  std::lock_guard lock(mutex_);
  return accepted_;
}

void SqliteRecorder::onEvent(const Event& event) {
  const auto* phase = std::get_if<PhaseEvent>(&event.payload);
  if (phase != nullptr && phase->boundary == PhaseBoundary::Start) return;  // stored once, at its end
  std::lock_guard lock(mutex_);
  if (closed_) return;
  pending_.append(event);
  ++accepted_;
  if (pending_.events() >= static_cast<std::size_t>(db_->options.batch_events) ||
      event.t - last_handover_t_ >= db_->options.batch_seconds || pending_.bytes() >= kMaxBatchBytes) {
    last_handover_t_ = event.t;
    handOverLocked();
  }
}

void SqliteRecorder::handOver(bool close) {
  std::lock_guard lock(mutex_);
  if (closed_) return;
  handOverLocked();
  closed_ = close;
}

void SqliteRecorder::handOverLocked() {
  if (pending_.empty()) return;
  ResultsDb::Impl::Batch batch{run_id_, std::move(pending_)};
  pending_ = EventBatch(batchReserve(db_->options));
  db_->enqueue(std::move(batch));
}

}  // namespace dash::log
