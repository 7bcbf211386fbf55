#pragma once
// Private to engine/log: the state shared by ResultsDb and its recorders.
#include <map>
#include <mutex>
#include <set>
#include <string>

#include "engine/core/stopwatch.h"
#include "engine/log/results_db.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

struct ResultsDb::Impl {
  std::string path;
  OpenMode mode = OpenMode::ReadWrite;
  DbOptions options;
  sql::Connection db;
  mutable std::mutex mutex;  ///< guards everything below and every use of `db`

  // The batched write transaction (writer only).
  bool in_transaction = false;
  std::int64_t pending = 0;
  Clock::time_point transaction_start;

  // Prepared once, used by every recorder.
  sql::Statement insert_event, insert_constraint, insert_expansion, insert_phase, insert_counter, insert_progress;

  std::set<std::string> parameter_names;  ///< every scenario parameter name in dash_experiments

  struct ActiveRun {
    std::int64_t run_id = 0;
    Clock::time_point start;
    SqliteRecorder* recorder = nullptr;
  };
  std::map<std::string, ActiveRun> active;  ///< runs begun by this object and not yet finished

  void requireWritable() const;
  /// Opens the batched transaction if none is open.
  void beginWriteLocked();
  /// Counts one write; commits when the batch is full or old enough.
  void afterWriteLocked();
  void commitLocked();
  /// After a failed statement: roll back whatever is open so later calls start clean.
  void rollbackLocked() noexcept;
};

}  // namespace dash::log
