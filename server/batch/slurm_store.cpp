#include "server/batch/slurm_store.h"

#include <sqlite3.h>

#include "engine/log/sqlite_util.h"

namespace dash::batch {

namespace sql = log::sql;

namespace {

constexpr const char* kSlurmTables = R"sql(
CREATE TABLE IF NOT EXISTS dash_slurm_jobs (
  batch_id TEXT NOT NULL,
  submission INTEGER NOT NULL,
  job_id TEXT NOT NULL,
  shard_dir TEXT NOT NULL,
  tasks INTEGER NOT NULL,
  submitted TEXT NOT NULL,
  cancelled INTEGER NOT NULL DEFAULT 0,
  options TEXT NOT NULL DEFAULT '{}',
  PRIMARY KEY (batch_id, submission)
);
CREATE TABLE IF NOT EXISTS dash_slurm_tasks (
  batch_id TEXT NOT NULL,
  submission INTEGER NOT NULL,
  task INTEGER NOT NULL,
  state TEXT NOT NULL,
  source TEXT NOT NULL DEFAULT '',
  shard_stamp TEXT NOT NULL DEFAULT '',
  PRIMARY KEY (batch_id, submission, task)
) WITHOUT ROWID;
CREATE TABLE IF NOT EXISTS dash_slurm_runs (
  batch_id TEXT NOT NULL,
  submission INTEGER NOT NULL,
  run_key TEXT NOT NULL,
  task INTEGER NOT NULL,
  PRIMARY KEY (batch_id, submission, run_key)
) WITHOUT ROWID;
)sql";

constexpr int kBusyTimeoutMs = 5000;

}  // namespace

struct SlurmStore::Impl {
  sql::Connection db;
  bool has_tables = true;
};

SlurmStore::SlurmStore(const std::string& path, log::OpenMode mode) : impl_(new Impl) {
  try {
    const bool writable = mode == log::OpenMode::ReadWrite;
    impl_->db = sql::open(path, writable ? SQLITE_OPEN_READWRITE : SQLITE_OPEN_READONLY);
    sqlite3_busy_timeout(impl_->db.get(), kBusyTimeoutMs);
    if (writable) {
      sql::exec(impl_->db.get(), kSlurmTables);
    } else {
      impl_->has_tables =
          sql::selectInt(impl_->db.get(),
                         "SELECT COUNT(*) FROM sqlite_master WHERE type = 'table' AND name = 'dash_slurm_jobs'") > 0;
    }
  } catch (...) {
    delete impl_;
    throw;
  }
}

SlurmStore::~SlurmStore() { delete impl_; }

void SlurmStore::addJob(const SlurmJobRecord& job, const std::vector<std::vector<std::string>>& task_keys) {
  sqlite3* db = impl_->db.get();
  sql::exec(db, "BEGIN IMMEDIATE");
  try {
    sql::Statement st(db,
                      "INSERT INTO dash_slurm_jobs (batch_id, submission, job_id, shard_dir, tasks, submitted, "
                      "cancelled, options) VALUES (?, ?, ?, ?, ?, ?, ?, ?)");
    st.bind(1, job.batch_id).bind(2, job.submission).bind(3, job.job_id).bind(4, job.shard_dir).bind(5, job.tasks);
    st.bind(6, job.submitted).bind(7, job.cancelled ? 1 : 0).bind(8, job.options_json).run();
    sql::Statement task(db, "INSERT INTO dash_slurm_tasks (batch_id, submission, task, state) VALUES (?, ?, ?, 'pending')");
    sql::Statement run(db, "INSERT INTO dash_slurm_runs (batch_id, submission, run_key, task) VALUES (?, ?, ?, ?)");
    for (std::size_t t = 0; t < task_keys.size(); ++t) {
      task.bind(1, job.batch_id).bind(2, job.submission).bind(3, static_cast<int>(t)).run();
      for (const std::string& key : task_keys[t]) {
        run.bind(1, job.batch_id).bind(2, job.submission).bind(3, key).bind(4, static_cast<int>(t)).run();
      }
    }
    sql::exec(db, "COMMIT");
  } catch (...) {
    sqlite3_exec(db, "ROLLBACK", nullptr, nullptr, nullptr);
    throw;
  }
}

std::vector<SlurmJobRecord> SlurmStore::jobs(const std::string& batch_id) const {
  std::vector<SlurmJobRecord> out;
  if (!impl_->has_tables) return out;
  sql::Statement st(impl_->db.get(),
                    "SELECT submission, job_id, shard_dir, tasks, submitted, cancelled, options FROM dash_slurm_jobs "
                    "WHERE batch_id = ? ORDER BY submission");
  st.bind(1, batch_id);
  while (st.step()) {
    SlurmJobRecord j;
    j.batch_id = batch_id;
    j.submission = static_cast<int>(st.columnInt(0));
    j.job_id = st.columnText(1);
    j.shard_dir = st.columnText(2);
    j.tasks = static_cast<int>(st.columnInt(3));
    j.submitted = st.columnText(4);
    j.cancelled = st.columnInt(5) != 0;
    j.options_json = st.columnText(6);
    out.push_back(std::move(j));
  }
  return out;
}

std::vector<std::string> SlurmStore::batchIds() const {
  std::vector<std::string> out;
  if (!impl_->has_tables) return out;
  sql::Statement st(impl_->db.get(), "SELECT DISTINCT batch_id FROM dash_slurm_jobs ORDER BY batch_id");
  while (st.step()) out.push_back(st.columnText(0));
  return out;
}

void SlurmStore::setCancelled(const std::string& batch_id, int submission) {
  sql::Statement st(impl_->db.get(), "UPDATE dash_slurm_jobs SET cancelled = 1 WHERE batch_id = ? AND submission = ?");
  st.bind(1, batch_id).bind(2, submission).run();
}

std::vector<SlurmTaskRecord> SlurmStore::tasks(const std::string& batch_id, int submission) const {
  std::vector<SlurmTaskRecord> out;
  if (!impl_->has_tables) return out;
  sql::Statement st(impl_->db.get(),
                    "SELECT task, state, source, shard_stamp FROM dash_slurm_tasks WHERE batch_id = ? AND submission = ? "
                    "ORDER BY task");
  st.bind(1, batch_id).bind(2, submission);
  while (st.step()) {
    out.push_back(SlurmTaskRecord{.task = static_cast<int>(st.columnInt(0)),
                                  .state = st.columnText(1),
                                  .source = st.columnText(2),
                                  .shard_stamp = st.columnText(3)});
  }
  return out;
}

void SlurmStore::setTaskState(const std::string& batch_id, int submission, int task, const std::string& state,
                              const std::string& source) {
  sql::Statement st(impl_->db.get(),
                    "UPDATE dash_slurm_tasks SET state = ?, source = ? WHERE batch_id = ? AND submission = ? AND task = ?");
  st.bind(1, state).bind(2, source).bind(3, batch_id).bind(4, submission).bind(5, task).run();
}

void SlurmStore::setShardStamp(const std::string& batch_id, int submission, int task, const std::string& stamp) {
  sql::Statement st(impl_->db.get(),
                    "UPDATE dash_slurm_tasks SET shard_stamp = ? WHERE batch_id = ? AND submission = ? AND task = ?");
  st.bind(1, stamp).bind(2, batch_id).bind(3, submission).bind(4, task).run();
}

std::map<std::string, int> SlurmStore::runTasks(const std::string& batch_id, int submission) const {
  std::map<std::string, int> out;
  if (!impl_->has_tables) return out;
  sql::Statement st(impl_->db.get(), "SELECT run_key, task FROM dash_slurm_runs WHERE batch_id = ? AND submission = ?");
  st.bind(1, batch_id).bind(2, submission);
  while (st.step()) out[st.columnText(0)] = static_cast<int>(st.columnInt(1));
  return out;
}

}  // namespace dash::batch
