#pragma once
// Private to engine/log: the state shared by ResultsDb, its recorders and its writer thread.
//
// Threads and locks. Recorders copy events into a batch under their own mutex and hand full
// batches to `queue` (queue_mutex). One writer thread drains the queue into SQLite under `mutex`,
// which also guards every other use of the connection. Lock order: a recorder's mutex, then
// queue_mutex; `mutex` is never held while waiting for the queue, so nothing waits in a circle.
#include <array>
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "engine/core/stopwatch.h"
#include "engine/events/event_batch.h"
#include "engine/events/event_emitter.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

/// What a run's stored events add up to: the figures finishRun fills in when a summary leaves them
/// unset.
struct RunFigures {
  RepresentationSizes sizes;
  PhaseTotals phases{};
  std::array<std::int64_t, kConstraintKindCount> constraints{};  ///< created, per kind
  std::int64_t active_constraints = 0;                          ///< created minus lifted
  std::int64_t expansions = 0;
  std::map<std::string, std::int64_t, std::less<>> counters;  ///< the latest value of each counter
  std::int64_t max_iteration = 0;
  double last_t = 0.0;
  std::int64_t events = 0;  ///< rows in the event tables (a phase counts once, at its end)
};

struct ResultsDb::Impl {
  std::string path;
  OpenMode mode = OpenMode::ReadWrite;
  DbOptions options;
  sql::Connection db;
  mutable std::mutex mutex;  ///< guards `db`, the statements, run_states, active, parameter_names

  bool in_transaction = false;

  // Prepared once, used by the writer thread (and finishRun for the last progress row).
  // insert_events inserts kRowsPerInsert representation events at once: most of a row's cost in
  // SQLite is per statement run, and representation events are the bulk of every stream.
  static constexpr int kRowsPerInsert = 64;
  sql::Statement insert_event, insert_events, insert_constraint, insert_expansion, insert_phase, insert_counter,
      insert_progress;

  std::set<std::string> parameter_names;  ///< every scenario parameter name in dash_experiments

  struct ActiveRun {
    std::int64_t run_id = 0;
    Clock::time_point start;
    SqliteRecorder* recorder = nullptr;
  };
  std::map<std::string, ActiveRun> active;  ///< runs begun by this object and not yet finished

  /// What the writer keeps per recorded run: the figures of the events written so far (for progress
  /// snapshots, and for finishRun, which would otherwise derive them with SQL), and the next seq.
  struct RunState {
    std::int64_t seq = 0;
    RunFigures figures;
    std::int64_t roadmap_vertices = 0, roadmap_edges = 0;
    std::int64_t checks_eager = 0, checks_lazy = 0, checks_total = -1;
    double progress_interval = 0.05;
    double last_progress_t = -1e300;
    /// The latest ProgressEvent (phase -1: none yet), in every progress snapshot from then on.
    int work_phase = -1;
    std::int64_t work_done = 0, work_total = 0;
    double work_rate = 0.0;
    std::string work_current;
    std::string error;  ///< the first write failure; events after it are dropped (figures no longer match)
    std::string ids_buffer;
  };
  std::map<std::int64_t, RunState> run_states;  ///< by run id

  /// Representation events waiting for a full insert_events (they point into batches of the
  /// current drain, which outlive them: the writer flushes them before it commits).
  struct EventRow {
    std::int64_t run_id = 0, seq = 0;
    double t = 0.0;
    int iteration = 0;
    int layer = 0, kind = 0, change = 0;
    std::uint32_t id = 0;
    std::string_view arc_type, label;
    std::string head, tail;  ///< JSON arrays (hyperarcs); kept between rows so their buffers are reused
  };
  std::vector<EventRow> event_rows = std::vector<EventRow>(kRowsPerInsert);
  int pending_rows = 0;

  // The writer thread and its queue.
  struct Batch {
    std::int64_t run_id = 0;
    EventBatch events;
    std::uint64_t ticket = 0;  ///< enqueue order
  };
  std::mutex queue_mutex;
  std::condition_variable queue_changed;
  std::deque<Batch> queue;
  std::size_t queued_events = 0;
  std::uint64_t enqueued = 0;  ///< tickets handed out
  std::uint64_t written = 0;   ///< every batch up to this ticket is committed (or failed)
  bool stopping = false;
  std::thread writer;

  void requireWritable() const;
  void beginWriteLocked();
  void commitLocked();
  /// After a failed statement: roll back whatever is open so later calls start clean.
  void rollbackLocked() noexcept;

  /// Hands a batch to the writer thread (started on first use); blocks while the queue holds more
  /// than options.max_queued_events.
  void enqueue(Batch batch);
  /// Returns once every batch enqueued before the call is committed (later ones may still wait:
  /// other runs' recorders cannot hold up a finishRun).
  void waitDrained();
  void stopWriter();
  void writerLoop();
  void writeEventLocked(std::int64_t run_id, RunState& state, const EventView& event);
  // writeEventLocked's kinds of event with a step of their own.
  void writeRepresentationLocked(std::int64_t run_id, std::int64_t seq, RunState& state, const EventView& event);
  void writeConstraintLocked(std::int64_t run_id, std::int64_t seq, RunState& state, const EventView& event);
  void writeCounterLocked(std::int64_t run_id, std::int64_t seq, RunState& state, const EventView& event);
  /// Inserts the representation events still waiting in event_rows.
  void flushEventRowsLocked();
  void writeProgressLocked(std::int64_t run_id, RunState& state, double t, int iteration);
};

}  // namespace dash::log
