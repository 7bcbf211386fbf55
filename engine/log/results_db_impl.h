#pragma once
// Private to engine/log: the state shared by ResultsDb, its recorders and its writer thread.
//
// Threads and locks. Recorders copy events into a batch under their own mutex and hand full
// batches to `queue` (queue_mutex). One writer thread drains the queue into SQLite under `mutex`,
// which also guards every other use of the connection. Lock order: a recorder's mutex, then
// queue_mutex; `mutex` is never held while waiting for the queue, so nothing waits in a circle.
#include <condition_variable>
#include <deque>
#include <map>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "engine/core/stopwatch.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

struct ResultsDb::Impl {
  std::string path;
  OpenMode mode = OpenMode::ReadWrite;
  DbOptions options;
  sql::Connection db;
  mutable std::mutex mutex;  ///< guards `db`, the statements, run_states, active, parameter_names

  bool in_transaction = false;

  // Prepared once, used by the writer thread (and finishRun for the last progress row).
  sql::Statement insert_event, insert_constraint, insert_expansion, insert_phase, insert_counter, insert_progress;

  std::set<std::string> parameter_names;  ///< every scenario parameter name in dash_experiments

  struct ActiveRun {
    std::int64_t run_id = 0;
    Clock::time_point start;
    SqliteRecorder* recorder = nullptr;
  };
  std::map<std::string, ActiveRun> active;  ///< runs begun by this object and not yet finished

  /// What the writer keeps per recorded run (derived sizes for progress snapshots, the next seq).
  struct RunState {
    std::int64_t seq = 0;
    RepresentationSizes sizes;
    std::int64_t active_constraints = 0;
    std::int64_t roadmap_vertices = 0, roadmap_edges = 0;
    std::int64_t checks_eager = 0, checks_lazy = 0, checks_total = -1;
    double progress_interval = 0.05;
    double last_progress_t = -1e300;
    std::string error;  ///< the first write failure; events after it are dropped
    std::string head_buffer, tail_buffer;
  };
  std::map<std::int64_t, RunState> run_states;  ///< by run id

  // The writer thread and its queue.
  struct Batch {
    std::int64_t run_id = 0;
    std::vector<Event> events;
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
  void writeEventLocked(std::int64_t run_id, RunState& state, const Event& event);
  void writeProgressLocked(std::int64_t run_id, RunState& state, double t, int iteration);
};

}  // namespace dash::log
