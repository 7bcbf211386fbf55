// A writer killed with SIGKILL mid-run leaves a sound file that keeps every finished run.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "engine/log/results_db.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

constexpr int kFinishedRuns = 3;

// The child: finishes kFinishedRuns runs (reporting each on `report_fd`), then starts one more and
// writes events into it until it is killed. Small commit batches make a kill mid-commit likely.
[[noreturn]] void writerChild(const std::string& path, int report_fd) {
  try {
    ResultsDb db(path, OpenMode::ReadWrite, DbOptions{.batch_events = 64, .batch_seconds = 0.01});
    for (int i = 0; i < kFinishedRuns; ++i) {
      testing::recordRun(db, testing::sampleMeta("sorting", R"({"robots":2,"objects":4})", "lazy-dash", i), 40);
      const char done = 'r';
      if (write(report_fd, &done, 1) != 1) _exit(3);
    }
    const std::string uuid = db.beginRun(testing::sampleMeta("sorting", R"({"robots":2,"objects":4})", "lazy-dash", 99));
    auto recorder = db.recorder(uuid);
    EventEmitter em(recorder.get());
    const char started = 's';
    if (write(report_fd, &started, 1) != 1) _exit(3);
    for (std::uint32_t i = 0;; ++i) {
      em.setIteration(static_cast<int>(i / 100));
      em.hyperarc(Layer::Motion, "move", i, {i + 1}, {i}, "a label long enough to fill pages quickly");
    }
  } catch (...) {
    _exit(4);
  }
}

void killMidRun(const std::string& path, std::chrono::milliseconds after_start) {
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    close(fds[0]);
    writerChild(path, fds[1]);
  }
  close(fds[1]);
  char reports[kFinishedRuns + 1];
  std::size_t got = 0;
  while (got < sizeof(reports)) {
    const ssize_t n = read(fds[0], reports + got, sizeof(reports) - got);
    ASSERT_GT(n, 0) << "the writer died early";
    got += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  std::this_thread::sleep_for(after_start);
  ASSERT_EQ(kill(child, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status));
  ASSERT_EQ(WTERMSIG(status), SIGKILL);
}

TEST(Crash, SigkillMidRunKeepsEveryFinishedRunAndASoundFile) {
  std::int64_t reference_events = 0;
  {
    testing::TempDir dir;
    ResultsDb db(dir.file("reference.db"));
    reference_events = db.getRun(testing::recordRun(db, testing::sampleMeta(), 40))->event_count;
    ASSERT_GT(reference_events, 500);
  }
  for (int delay_ms : {0, 7, 40}) {
    testing::TempDir dir;
    const std::string path = dir.file("crash.db");
    killMidRun(path, std::chrono::milliseconds(delay_ms));
    if (HasFatalFailure()) return;

    EXPECT_EQ(testing::integrityCheck(path), "ok") << "killed " << delay_ms << " ms into the last run";
    ResultsDb db(path);
    EXPECT_EQ(testing::integrityCheck(path), "ok");
    const auto solved = db.listRuns(RunFilter{.status = RunStatus::Solved});
    ASSERT_EQ(solved.size(), static_cast<std::size_t>(kFinishedRuns)) << "killed " << delay_ms << " ms in";
    for (const RunRecord& run : solved) {
      // Each finished run has all its events: as many rows as the same script gives in a clean file.
      EXPECT_EQ(run.event_count, reference_events);
      const auto stored = db.select("SELECT COUNT(*) FROM dash_timeline WHERE run_id = ?", {run.id});
      EXPECT_EQ(std::get<std::int64_t>(stored.rows.at(0).at(0)), reference_events);
    }
    const auto running = db.listRuns(RunFilter{.status = RunStatus::Running});
    ASSERT_EQ(running.size(), 1u);
    EXPECT_EQ(db.markInterrupted(), 1);
    const auto crashed = db.getRun(running.front().meta.uuid);
    EXPECT_EQ(crashed->status, RunStatus::Crashed);
    EXPECT_EQ(crashed->summary.sizes->hyperarcs[static_cast<int>(Layer::Motion)], crashed->event_count);
    EXPECT_EQ(testing::integrityCheck(path), "ok");
  }
}

}  // namespace
}  // namespace dash::log
