// The Slurm backend on a real one-node cluster (slurm_cluster.h): a tiny batch through
// `--backend slurm` gives the same runs and statuses as the local runner; a requeued task adds no
// run twice; a batch cancelled mid-way (scancel) resumes with exactly its missing runs.
// Skipped (exit code 77, CTest's SKIP_RETURN_CODE) when not root or without slurm-wlm and munge.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include "engine/log/results_db.h"
#include "server/batch/slurm_backend.h"
#include "server/batch/slurm_client.h"
#include "tests/common/temp_dir.h"
#include "tests/slurm/slurm_cluster.h"

namespace dash::batch::testing {
namespace {

namespace fs = std::filesystem;

using test::TempDir;

/// The dashbench binary with `args`; its exit code and stdout (stderr goes to the test's log).
CommandResult dashbench(const std::vector<std::string>& args, double timeout = 120.0) {
  std::vector<std::string> argv = {DASHBENCH_BINARY};
  argv.insert(argv.end(), args.begin(), args.end());
  CommandResult r = runCommand(argv, timeout);
  if (!r.err.empty()) std::fprintf(stderr, "[dashbench %s] %s", args.front().c_str(), r.err.c_str());
  return r;
}

/// Sorting, 2 robots and 2 objects, with the seeds and planners given. The tests plan the task
/// layer only (task_only: milliseconds per run): what they check is the backend, not the planner.
std::string tinySpec(const std::string& name, const std::string& seeds, const std::string& planners) {
  return R"({"name": ")" + name + R"(", "time_limit": 30, "memory_limit": 2048,
    "scenarios": [{"family": "sorting", "params": {"robots": 2, "objects": 2}}],
    "planners": )" + planners + R"(, "seeds": )" + seeds + "}";
}

/// key -> status of the batch's runs (through the run list), and the number of dash_runs rows.
struct Outcome {
  std::map<std::string, std::string> status;
  std::int64_t rows = 0;
};

Outcome outcomeOf(const std::string& db_path, const std::string& batch_id) {
  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  Outcome o;
  const log::SqlRows rows = db.select(
      "SELECT b.run_key, r.status FROM dash_batch_runs b JOIN dash_runs r ON r.uuid = b.run_uuid WHERE b.batch_id = ?",
      {batch_id});
  for (const auto& row : rows.rows) o.status[std::get<std::string>(row[0])] = std::get<std::string>(row[1]);
  const log::SqlRows count = db.select("SELECT COUNT(*) FROM dash_runs WHERE batch_id = ?", {batch_id});
  o.rows = std::get<std::int64_t>(count.rows[0][0]);
  return o;
}

std::string onlyBatchId(const std::string& db_path) {
  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const auto batches = db.listBatches();
  return batches.size() == 1 ? batches.front().id : "";
}

/// Polls `done` every 200 ms for up to `seconds`.
template <class F>
bool waitFor(double seconds, F done) {
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < until) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  return done();
}

const char* const kTwoPlanners =
    R"([{"name": "lazy-dash", "settings": {"task_only": true}, "label": "lazy-task"},
        {"name": "lazy-dash", "settings": {"test_fault": "abort"}, "label": "crash"}])";

TEST(SlurmCluster, SlurmBatchMatchesTheLocalBatch) {
  const TempDir tmp;
  const std::string spec = tmp.write("tiny.json", tinySpec("tiny", "[1, 2]", kTwoPlanners));
  const std::string local_db = tmp.file("local.db");
  const std::string slurm_db = tmp.file("slurm.db");

  ASSERT_EQ(dashbench({"batch", "run", spec, "--db", local_db, "--quiet"}).exit_code, 0);
  const CommandResult run = dashbench(
      {"batch", "run", spec, "--db", slurm_db, "--backend", "slurm", "--max-parallel", "2", "--poll", "0.5", "--quiet"});
  ASSERT_EQ(run.exit_code, 0) << run.out;
  EXPECT_NE(run.out.find(": finished  4/4 runs"), std::string::npos) << run.out;

  const std::string local_id = onlyBatchId(local_db);
  const std::string slurm_id = onlyBatchId(slurm_db);
  ASSERT_FALSE(slurm_id.empty());
  const Outcome local = outcomeOf(local_db, local_id);
  const Outcome slurm = outcomeOf(slurm_db, slurm_id);
  ASSERT_EQ(local.status.size(), 4u);
  EXPECT_EQ(slurm.status, local.status);  // same keys, same statuses (solved and crashed)
  EXPECT_EQ(slurm.rows, 4);
  int solved = 0;
  for (const auto& [key, status] : slurm.status) solved += status == "solved" ? 1 : 0;
  EXPECT_EQ(solved, 2);

  // The job script: one task per run, two at once, one CPU, time and memory from the limits.
  const std::string script_path = slurm_db + ".slurm/" + slurm_id + "/s1/job.sbatch";
  std::ifstream script_in(script_path);
  std::stringstream script;
  script << script_in.rdbuf();
  EXPECT_NE(script.str().find("#SBATCH --array=0-3%2\n"), std::string::npos) << script.str();
  EXPECT_NE(script.str().find("#SBATCH --cpus-per-task=1\n"), std::string::npos);
  EXPECT_NE(script.str().find("#SBATCH --time=0:03:00\n"), std::string::npos);  // 30 * 1.25 + 60 + 60 s
  EXPECT_NE(script.str().find("#SBATCH --mem=2765M\n"), std::string::npos);

  // Status shows the Slurm states next to the runs.
  const CommandResult status = dashbench({"batch", "status", "--db", slurm_db, slurm_id});
  EXPECT_EQ(status.exit_code, 0);
  EXPECT_NE(status.out.find("4 completed"), std::string::npos) << status.out;
  EXPECT_NE(status.out.find("solved  sorting/"), std::string::npos) << status.out;

  // A requeued task (as after a node failure) whose shard was lost runs its run again, under a new
  // uuid; the key already has a result, so the copy is dropped when merged: nothing twice.
  SlurmBackend backend(slurm_db);
  const SlurmBatchView done = backend.update(slurm_id);
  const std::string job = done.tasks.front().job_id;
  fs::remove(slurm_db + ".slurm/" + slurm_id + "/s1/task-0.db");
  const CommandResult requeue = runCommand({"scontrol", "requeue", job + "_0"});
  ASSERT_EQ(requeue.exit_code, 0) << requeue.err;
  // Slurm holds a requeued job back (reason BeginTime) for a while; let it start now.
  runCommand({"scontrol", "update", "JobId=" + job + "_0", "StartTime=now"});
  SlurmClient client;
  EXPECT_TRUE(waitFor(60, [&] {
    const auto q = client.queue(job);
    return q && q->count(0) != 0 && q->at(0) == SlurmState::kCompleted;
  }));
  ASSERT_TRUE(fs::exists(slurm_db + ".slurm/" + slurm_id + "/s1/task-0.db"));  // the rerun's shard
  const SlurmBatchView after_requeue = backend.update(slurm_id);
  EXPECT_EQ(after_requeue.merged, 0);  // the rerun's copy was not adopted
  EXPECT_EQ(after_requeue.status, "finished");
  const Outcome again = outcomeOf(slurm_db, slurm_id);
  EXPECT_EQ(again.status, local.status);
  EXPECT_EQ(again.rows, 4);
}

TEST(SlurmCluster, CancelMidwayThenResume) {
  const TempDir tmp;
  const std::string spec = tmp.write(
      "six.json", tinySpec("six", "[1, 2, 3, 4, 5, 6]", R"([{"name": "lazy-dash", "settings": {"task_only": true}, "label": "lazy-task"}])"));
  const std::string db = tmp.file("six.db");
  const CommandResult submitted = dashbench(
      {"batch", "run", spec, "--db", db, "--backend", "slurm", "--max-parallel", "1", "--detach", "--id", "six-1"});
  ASSERT_EQ(submitted.exit_code, 0) << submitted.out;
  SlurmBackend backend(db);
  // Cancel once the first task has merged its run: the others are still pending or running.
  ASSERT_TRUE(waitFor(90, [&] { return backend.update("six-1").complete >= 1; }));
  ASSERT_EQ(dashbench({"batch", "cancel", "--db", db, "six-1"}).exit_code, 0);
  ASSERT_TRUE(waitFor(60, [&] { return !backend.update("six-1").active; }));
  const SlurmBatchView cancelled = backend.update("six-1");
  EXPECT_EQ(cancelled.status, "cancelled");
  EXPECT_GE(cancelled.complete, 1);
  EXPECT_LT(cancelled.complete, 6);
  EXPECT_GE(cancelled.by_state.count(SlurmState::kCancelled), 1u);
  const Outcome before = outcomeOf(db, "six-1");
  EXPECT_LE(before.rows, 6);

  const CommandResult resumed = dashbench({"batch", "resume", "--db", db, "six-1", "--poll", "0.5", "--quiet"});
  ASSERT_EQ(resumed.exit_code, 0) << resumed.out;
  const Outcome after = outcomeOf(db, "six-1");
  ASSERT_EQ(after.status.size(), 6u);
  for (const auto& [key, status] : after.status) {
    EXPECT_EQ(status, "solved") << key;
  }
  EXPECT_EQ(after.rows, 6);  // never a run twice
  // Runs finished before the cancel kept their rows; only the missing ones were resubmitted.
  for (const auto& [key, status] : before.status) {
    if (status == "solved") {
      EXPECT_EQ(after.status.at(key), "solved");
    }
  }
  const SlurmBatchView view = backend.update("six-1");
  EXPECT_EQ(view.status, "finished");
  int resubmitted = 0;
  for (const SlurmTaskView& t : view.tasks) resubmitted += t.submission == 2 ? static_cast<int>(t.keys.size()) : 0;
  EXPECT_EQ(resubmitted, 6 - static_cast<int>(cancelled.complete));
}

}  // namespace
}  // namespace dash::batch::testing

int main(int argc, char** argv) {
  using dash::batch::testing::SlurmCluster;
  const std::string reason = SlurmCluster::unavailableReason();
  if (!reason.empty()) {
    std::printf("SKIPPED: %s\n", reason.c_str());
    return 77;  // CTest's SKIP_RETURN_CODE for this test
  }
  ::testing::InitGoogleTest(&argc, argv);
  SlurmCluster cluster;
  std::string error;
  if (!cluster.start(60, error)) {
    std::printf("FAILED: the one-node Slurm cluster did not start: %s\n", error.c_str());
    return 1;
  }
  const int result = RUN_ALL_TESTS();
  const bool stopped = cluster.stop();
  if (!stopped) std::printf("FAILED: a Slurm daemon ignored SIGTERM\n");
  return stopped ? result : 1;
}
