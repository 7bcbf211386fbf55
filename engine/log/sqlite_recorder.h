#pragma once
// The event sink that records one run into a ResultsDb: representation elements to dash_events,
// constraints, task space expansions, phase intervals and counters to their tables, and a
// snapshot of the representation sizes to dash_progress (Planner Arena's `progress`) at phase
// ends, at most every `progress_interval` seconds of run time, plus a last one at finishRun.
//
// Cost per event: one mutex, one prepared INSERT inside the database's batched transaction.
// onEvent never throws into the planner: a database failure stops the recording, and finishRun
// reports it in the run's error text.
#include <array>
#include <cstdint>
#include <string>

#include "engine/log/events.h"
#include "engine/log/results_db.h"

namespace dash::log {

struct RecorderOptions {
  double progress_interval = 0.05;  ///< seconds of run time between progress snapshots
};

class SqliteRecorder final : public EventSink {
 public:
  ~SqliteRecorder() override;
  SqliteRecorder(const SqliteRecorder&) = delete;
  SqliteRecorder& operator=(const SqliteRecorder&) = delete;

  void onEvent(const Event& event) override;

  const std::string& runUuid() const { return uuid_; }
  /// Events stored so far (phase starts excluded: an interval is stored once, at its end).
  std::int64_t storedEvents() const;
  /// The first database error, if recording stopped; empty otherwise.
  std::string error() const;

 private:
  friend class ResultsDb;
  friend struct ResultsDb::Impl;
  SqliteRecorder(ResultsDb::Impl& db, std::string uuid, std::int64_t run_id, RecorderOptions options);

  void writeRepresentation(const Event& e, const RepresentationEvent& r);
  void writeConstraint(const Event& e, const ConstraintEvent& c);
  void writeExpansion(const Event& e, const TaskSpaceExpansionEvent& x);
  void writePhase(const Event& e, const PhaseEvent& p);
  void writeCounter(const Event& e, const CounterEvent& c);
  void writeProgress(double t, int iteration);

  ResultsDb::Impl* db_;  ///< nullptr once the database is closed
  std::string uuid_;
  std::int64_t run_id_;
  RecorderOptions options_;
  bool finished_ = false;
  std::string error_;

  // Running state (guarded by the database's mutex).
  std::int64_t seq_ = 0;
  RepresentationSizes sizes_;
  std::int64_t active_constraints_ = 0;
  std::int64_t roadmap_vertices_ = 0, roadmap_edges_ = 0;
  std::int64_t checks_eager_ = 0, checks_lazy_ = 0, checks_total_ = -1;
  double last_progress_t_ = -1e300;
  std::string head_buffer_, tail_buffer_;
};

}  // namespace dash::log
