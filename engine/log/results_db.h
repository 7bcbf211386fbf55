#pragma once
// The results database: one SQLite file holding every run's metadata, outcome and full event
// history, readable by Planner Arena (arena_views.h) and by the workbench's server.
//
// Concurrency: one writer process at a time (the batch runner or a single `dashbench plan`); any
// number of readers (the server, `dashbench db query`) may read while it writes (WAL mode).
// Within the writer, one ResultsDb may be shared by several threads: every call and every
// recorder serialises on one mutex.
//
// Durability: recorders hand events in batches (every N events or T seconds of run time) to a
// writer thread, which commits each drain as one transaction. beginRun and finishRun commit
// before they return (finishRun after the run's last events), so a process killed at any moment (SIGKILL
// included) leaves a file that passes integrity_check and holds every run finished before the
// kill; the killed run stays 'running' until markInterrupted() closes it.
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "engine/events/event_emitter.h"
#include "engine/events/events.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

class SqliteRecorder;
struct RecorderOptions;

enum class RunStatus { Running, Solved, Timeout, Infeasible, Crashed, Cancelled };
const char* toString(RunStatus status);
/// Throws InputError for an unknown name.
RunStatus parseRunStatus(const std::string& name);

/// Vertices and hyperarcs per layer, indexed by Layer.
struct RepresentationSizes {
  std::array<std::int64_t, kLayerCount> vertices{};
  std::array<std::int64_t, kLayerCount> hyperarcs{};
};

/// What is known when a run starts. Empty strings take the defaults noted.
struct RunMetadata {
  std::string uuid;      ///< empty: a new random (version 4) UUID
  std::string batch_id;  ///< empty: not part of a batch
  std::string family;    ///< scenario family: "sorting", "wall", ... (required)
  std::string scene;     ///< the scene's name, if any
  std::string params_json = "{}";  ///< scenario parameters, a flat JSON object without the seed;
                                   ///< names: letters, digits, '_', '-', '.'
  std::uint64_t seed = 0;
  std::string planner;                         ///< "lazy-dash", "dash" (required)
  std::string planner_settings_json = "{}";    ///< a JSON object
  std::string planner_config_name;             ///< empty: planner, plus settings when not "{}"
  std::optional<double> time_limit;            ///< seconds
  std::optional<double> memory_limit;          ///< MB
  std::string code_version;                    ///< empty: this build's git describe (or the project version)
  std::string host;                            ///< empty: this machine's host name
  std::string cpu_info;                        ///< empty: this machine's CPU model and core count
};

/// What is known when a run ends. Unset fields are derived from the run's recorded events
/// (sizes, phase totals, counters) or left NULL (makespan, path length, memory).
struct RunSummary {
  RunStatus status = RunStatus::Solved;
  /// Seconds. With phase_accounting 2: the sum of the phases (phase_seconds); older runs (accounting
  /// unset): the planner's wall time. Unset: wall time since beginRun.
  std::optional<double> total_time;
  std::optional<double> wall_time;             ///< seconds of wall time of the planner's solve, beside total_time
  /// How phases were booked: 2 = one accounting for both planners, total = sum of the phases
  /// (docs/planners.md "Phases"); unset = before that (total was the wall time).
  std::optional<int> phase_accounting;
  std::optional<PhaseTotals> phase_seconds;    ///< unset: summed from phase events
  std::optional<RepresentationSizes> sizes;    ///< unset: counted from representation events
  std::optional<std::int64_t> iterations;      ///< unset: highest iteration number in the events
  std::optional<std::int64_t> roadmap_vertices;  ///< unset: latest "roadmap_vertices" counter
  std::optional<std::int64_t> roadmap_edges;     ///< unset: latest "roadmap_edges" counter
  std::optional<std::array<std::int64_t, kConstraintKindCount>> constraints;  ///< created, per kind
  std::optional<std::int64_t> task_space_expansions;
  std::optional<std::int64_t> collision_checks_eager;  ///< unset: latest counter of that name
  std::optional<std::int64_t> collision_checks_lazy;   ///< unset: latest counter of that name
  std::optional<double> makespan;        ///< seconds
  std::optional<double> path_length;     ///< radians (joint space), summed over robots
  std::optional<double> peak_memory_mb;
  std::string plan_json;  ///< the dashbench.plan/1 document, when solved
  std::string error;
  std::optional<int> exit_signal;  ///< the signal that ended a crashed child process
};

/// One stored run, as read back.
struct RunRecord {
  std::int64_t id = 0;  ///< local to this file (Planner Arena's runs.id); the uuid is global
  RunMetadata meta;
  RunStatus status = RunStatus::Running;
  std::string start_time;  ///< ISO 8601, UTC
  std::string end_time;
  RunSummary summary;
  std::optional<std::int64_t> collision_checks;
  std::int64_t event_count = 0;
  std::vector<std::string> tags;
  std::string note;
};

struct RunFilter {
  std::string batch_id;
  std::optional<RunStatus> status;
  std::string family;
  std::string planner;
  std::vector<std::string> uuids;  ///< empty: any
  std::int64_t limit = 1000;
  std::int64_t offset = 0;
  bool newest_first = true;
  bool include_plan = false;  ///< plans can be large
};

struct BatchRecord {
  std::string id;  ///< globally unique (merge keeps it)
  std::string name;
  std::string spec_json = "{}";
  std::string created;  ///< empty: now
  std::string status = "queued";
};

struct DbInfo {
  std::string path;
  int schema_version = 0;
  std::int64_t runs = 0;
  std::map<std::string, std::int64_t> runs_by_status;
  std::int64_t experiments = 0;
  std::int64_t planner_configs = 0;
  std::int64_t batches = 0;
  std::int64_t events = 0;  ///< rows in all event tables
};

struct MergeReport {
  std::int64_t added = 0;     ///< runs new to the output
  std::int64_t replaced = 0;  ///< runs the output had as 'running' and the input had finished
  std::int64_t skipped = 0;   ///< runs the output already had
  /// Dispatch records (keyed by their id, which carries a random per-server tag): new to the output,
  /// finished in the input but still active in the output (the input's copy wins), already present.
  /// An id the output holds for a different dispatch (other created time, client, scene, ...) is
  /// imported under that id plus a random suffix, counted as added.
  std::int64_t dispatches_added = 0;
  std::int64_t dispatches_replaced = 0;
  std::int64_t dispatches_skipped = 0;
};

enum class OpenMode { ReadWrite, ReadOnly };

struct DbOptions {
  int busy_timeout_ms = 5000;
  int batch_events = 4096;      ///< a recorder hands a batch to the writer thread at this many events...
  double batch_seconds = 0.25;  ///< ...or when this much run time passed since its last hand-over
  std::size_t max_queued_events = 1 << 16;  ///< recorders wait while the writer is this far behind
};

class ResultsDb {
 public:
  /// Opens (creating in ReadWrite mode) and migrates the file. Throws SchemaError for a newer or
  /// foreign file, DbError when SQLite cannot open it.
  explicit ResultsDb(const std::string& path, OpenMode mode = OpenMode::ReadWrite, DbOptions options = {});
  ~ResultsDb();  ///< writes every pending event; recorders still alive stop recording
  ResultsDb(const ResultsDb&) = delete;
  ResultsDb& operator=(const ResultsDb&) = delete;

  const std::string& path() const;
  int schemaVersion() const;

  // --- writing (ReadWrite only) ---
  /// Inserts the run as 'running'; returns its uuid. Throws InputError on bad metadata or a uuid
  /// that already exists.
  std::string beginRun(const RunMetadata& meta);
  /// An event sink for a run begun here; this ResultsDb must outlive it.
  std::unique_ptr<SqliteRecorder> recorder(const std::string& uuid);
  std::unique_ptr<SqliteRecorder> recorder(const std::string& uuid, const RecorderOptions& options);
  /// Commits the run's pending events, then its outcome. Throws InputError for an unknown or
  /// already finished run, or a summary with status Running.
  void finishRun(const std::string& uuid, const RunSummary& summary);
  /// Closes every run left 'running' by a process that died (not those begun by this object);
  /// their figures are derived from the events they recorded. Returns how many.
  int markInterrupted(const std::string& reason = "interrupted: the process ended before the run finished",
                      RunStatus status = RunStatus::Crashed);
  /// Hands over every recorder's pending events and returns once they are committed.
  void flush();

  void putBatch(const BatchRecord& batch);  ///< insert, or update name/spec/status
  void setBatchStatus(const std::string& id, const std::string& status);
  void addTag(const std::string& uuid, const std::string& tag);
  void removeTag(const std::string& uuid, const std::string& tag);
  void setNote(const std::string& uuid, const std::string& note);

  /// Adds every run of `other_path` whose uuid is new here, with its events, tags, batch,
  /// experiment and planner configuration (ids are remapped). A run this file has as 'running'
  /// and `other_path` has finished is replaced. Idempotent. An older input is migrated in a
  /// temporary copy; the input is never written.
  MergeReport mergeFrom(const std::string& other_path);

  /// Rebuilds the Planner Arena views if their definitions changed (done automatically).
  void refreshArenaViews();

  // --- reading ---
  std::vector<RunRecord> listRuns(const RunFilter& filter = {}) const;
  std::optional<RunRecord> getRun(const std::string& uuid) const;
  std::vector<BatchRecord> listBatches() const;
  DbInfo info() const;
  /// A trusted SELECT for the workbench's own queries (the user's SQL goes through runReadOnlyQuery).
  SqlRows select(const std::string& sql, const std::vector<SqlValue>& params = {}) const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

/// The calling process's peak resident memory in MB (getrusage): a run's peak memory when the run
/// has its own process.
double processPeakMemoryMb();

}  // namespace dash::log
