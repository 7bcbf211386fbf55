#pragma once
// The event sink that records one run into a ResultsDb: representation elements to dash_events,
// constraints, task space expansions, phase intervals and counters to their tables, and a
// snapshot of the representation sizes to dash_progress (Planner Arena's `progress`) at phase
// ends and as representation events arrive, at most every `progress_interval` seconds of run time,
// plus a last one at finishRun.
//
// The planner's thread only copies each event's fields into a flat batch buffer (event_batch.h: no
// allocation per event); the ResultsDb's writer thread turns full batches (DbOptions::batch_events,
// or batch_seconds of run time) into rows, a drain of the queue per transaction.
// finishRun hands over what is left and waits until it is committed. onEvent never throws into
// the planner: a database failure stops the recording, and finishRun reports it in the run's
// error text. Several threads may emit into one recorder.
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include "engine/events/event_batch.h"
#include "engine/events/events.h"
#include "engine/log/results_db.h"

namespace dash::log {

struct RecorderOptions {
  double progress_interval = 0.05;  ///< seconds of run time between progress snapshots
};

class SqliteRecorder final : public EventSink {
 public:
  /// Hands over the events not yet handed over (they are written even if finishRun never comes).
  /// Must not run concurrently with finishRun of the same run.
  ~SqliteRecorder() override;
  SqliteRecorder(const SqliteRecorder&) = delete;
  SqliteRecorder& operator=(const SqliteRecorder&) = delete;

  void onEvent(const Event& event) override;

  const std::string& runUuid() const { return uuid_; }
  /// Events accepted so far (phase starts excluded: an interval is stored once, at its end).
  std::int64_t acceptedEvents() const;

 private:
  friend class ResultsDb;
  SqliteRecorder(ResultsDb::Impl& db, std::string uuid, std::int64_t run_id);
  /// Hands over what is pending; with `close`, accepts nothing more.
  void handOver(bool close);
  void handOverLocked();

  ResultsDb::Impl* db_;
  const std::string uuid_;
  const std::int64_t run_id_;
  mutable std::mutex mutex_;
  EventBatch pending_;
  double last_handover_t_ = 0.0;
  std::int64_t accepted_ = 0;
  bool closed_ = false;
};

}  // namespace dash::log
