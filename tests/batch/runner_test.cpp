// BatchRunner end to end: runs in child processes (the dashbench binary's run-one), a crash, a
// hang past the time limit, cancel, and a runner killed with SIGKILL then resumed.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>
#include <thread>

#include "engine/core/stopwatch.h"
#include "engine/events/memory_sink.h"
#include "engine/log/sqlite_recorder.h"
#include "engine/planners/planner.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "server/batch/batch_store.h"
#include "server/batch/progress_printer.h"
#include "tests/batch/batch_test_util.h"
#include "tests/common/child_process.h"

namespace dash::batch {
namespace {

using namespace testing;
using log::RunStatus;

/// Collects the progress callbacks (called on the runner thread).
struct ProgressLog {
  std::mutex mutex;
  std::vector<FinishedRun> finished;
  std::int64_t max_running = 0;
  std::int64_t callbacks = 0;
  ProgressCallback callback() {
    return [this](const BatchProgress& p) {
      std::lock_guard lock(mutex);
      ++callbacks;
      max_running = std::max(max_running, p.running);
      if (p.finished) finished.push_back(*p.finished);
    };
  }
};

std::vector<log::RunRecord> batchRuns(const log::ResultsDb& db, const std::string& id) {
  return db.listRuns(log::RunFilter{.batch_id = id, .limit = 100000, .newest_first = false, .include_plan = true});
}

/// Net elements per (layer, kind) from a run's stored events.
std::map<std::pair<std::string, std::string>, std::int64_t> storedSizes(const log::ResultsDb& db, std::int64_t run_id) {
  std::map<std::pair<std::string, std::string>, std::int64_t> out;
  const auto rows = db.select(
      "SELECT layer, kind, SUM(CASE change WHEN 'added' THEN 1 ELSE -1 END) FROM dash_events WHERE run_id = ? "
      "GROUP BY layer, kind",
      {run_id});
  for (const auto& r : rows.rows) {
    out[{std::get<std::string>(r[0]), std::get<std::string>(r[1])}] = std::get<std::int64_t>(r[2]);
  }
  return out;
}

/// A finished run of the tiny batch: its metadata, figures, and sizes that match its stored events.
void expectTinyRunStored(const log::ResultsDb& db, const log::RunRecord& r, const std::string& id) {
  SCOPED_TRACE(r.meta.scene);
  EXPECT_EQ(r.status, RunStatus::Solved) << r.summary.error;
  EXPECT_EQ(r.meta.batch_id, id);
  EXPECT_EQ(r.meta.family, "sorting");
  EXPECT_EQ(r.meta.planner, "lazy-dash");
  EXPECT_EQ(r.meta.planner_config_name, "lazy-task");
  // The spec's settings, with the run's full effective parameter set beside them.
  const nlohmann::json settings = nlohmann::json::parse(r.meta.planner_settings_json);
  EXPECT_EQ(settings.at("task_only"), true) << r.meta.planner_settings_json;
  EXPECT_EQ(settings.at("parameters").at("schedule_memo"), true) << r.meta.planner_settings_json;
  EXPECT_EQ(r.meta.time_limit.value_or(0), 20.0);
  EXPECT_EQ(r.meta.memory_limit.value_or(0), 2048.0);
  EXPECT_EQ(r.meta.scene.rfind("sorting-", 0), 0u) << r.meta.scene;  // set once the child generated it
  EXPECT_GT(r.event_count, 0);
  ASSERT_TRUE(r.summary.total_time.has_value());
  EXPECT_GT(*r.summary.total_time, 0.0);
  EXPECT_GT(r.summary.peak_memory_mb.value_or(0), 1.0);
  ASSERT_TRUE(r.summary.sizes.has_value());
  EXPECT_GT(r.summary.sizes->vertices[0], 0);
  EXPECT_GT(r.summary.sizes->hyperarcs[0], 0);
  // The sizes the planner reported match the events that came through the pipe.
  const auto stored = storedSizes(db, r.id);
  for (int layer = 0; layer < log::kLayerCount; ++layer) {
    const auto get = [&](const char* kind) {
      const auto it = stored.find({log::kLayerNames[layer], kind});
      return it == stored.end() ? 0 : it->second;
    };
    EXPECT_EQ(get("vertex"), r.summary.sizes->vertices[layer]) << log::kLayerNames[layer];
    EXPECT_EQ(get("hyperarc"), r.summary.sizes->hyperarcs[layer]) << log::kLayerNames[layer];
  }
}

/// Every event the planner emits arrives: the first run against the same run done in this process.
void expectEveryEventArrives(const log::ResultsDb& db, const std::vector<log::RunRecord>& runs) {
  const log::RunRecord& first = runs.front();
  const Scene scene = generateScenario("sorting", ScenarioParams({{"robots", 4}, {"objects", 4}}), first.meta.seed,
                                       RobotLibrary::loadDefault());
  log::MemorySink sink;
  PlannerSettings settings;
  settings.seed = first.meta.seed;
  settings.task_only = true;
  const PlanResult direct = makePlanner("lazy-dash")->solve(scene, settings, Deadline(20), &sink);
  ASSERT_EQ(direct.outcome, PlanOutcome::kSolved);
  std::int64_t representation = 0, constraints = 0, expansions = 0, phase_ends = 0, counters = 0;
  for (const log::Event& e : sink.events()) {
    std::visit(
        [&](const auto& p) {
          using T = std::decay_t<decltype(p)>;
          if constexpr (std::is_same_v<T, log::RepresentationEvent>) ++representation;
          if constexpr (std::is_same_v<T, log::ConstraintEvent>) ++constraints;
          if constexpr (std::is_same_v<T, log::TaskSpaceExpansionEvent>) ++expansions;
          if constexpr (std::is_same_v<T, log::PhaseEvent>) phase_ends += p.boundary == log::PhaseBoundary::End;
          if constexpr (std::is_same_v<T, log::CounterEvent>) ++counters;
        },
        e.payload);
  }
  std::int64_t run_id = 0;
  for (const auto& r : runs) {
    if (r.meta.scene == scene.name) {
      run_id = r.id;
    }
  }
  ASSERT_NE(run_id, 0) << "no stored run of scene " << scene.name;
  const auto count = [&](const char* table) {
    return scalar(db, std::string("SELECT COUNT(*) FROM ") + table + " WHERE run_id = ?", {run_id});
  };
  EXPECT_EQ(count("dash_events"), representation);
  EXPECT_EQ(count("dash_constraints"), constraints);
  EXPECT_EQ(count("dash_expansions"), expansions);
  EXPECT_EQ(count("dash_phases"), phase_ends);
  EXPECT_EQ(count("dash_counters"), counters);
}

/// The stored run list and the batch row of a finished batch of 4 solved runs.
void expectFinishedBatchOfFour(const std::string& db_path, const std::string& id) {
  const BatchStore store(db_path, log::OpenMode::ReadOnly);
  const auto stored = store.runs(id);
  ASSERT_EQ(stored.size(), 4u);
  for (const StoredRun& s : stored) {
    EXPECT_FALSE(s.run_uuid.empty());
    EXPECT_EQ(s.attempts, 1);
    EXPECT_TRUE(s.complete());
  }
  EXPECT_FALSE(store.runner(id).has_value());  // cleared at the end
  const auto info = listBatchInfo(db_path, id);
  ASSERT_EQ(info.size(), 1u);
  EXPECT_EQ(info[0].status, "finished");
  EXPECT_EQ(info[0].total, 4);
  EXPECT_EQ(info[0].pending, 0);
  EXPECT_EQ(info[0].by_status.at("solved"), 4);
  EXPECT_NE(formatBatchInfo(info).find(id), std::string::npos);
}

TEST(BatchRunner, TinyBatchEndToEndWithTwoWorkers) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const BatchSpec spec = specOf(sortingSpec("[4, 8]", "[1, 2]", std::string("[") + kTaskOnly + "]"));
  ProgressLog progress;
  BatchRunner runner;
  const Stopwatch clock;
  const std::string id = runner.start(spec, db_path, testOptions(2), progress.callback());
  const BatchResult result = runner.wait();
  EXPECT_EQ(result.status, "finished") << result.error;
  EXPECT_EQ(result.batch_id, id);
  EXPECT_EQ(result.progress.total, 4);
  EXPECT_EQ(result.progress.done, 4);
  EXPECT_EQ(result.progress.solved, 4);
  EXPECT_EQ(result.progress.failed, 0);
  EXPECT_EQ(result.progress.remaining, 0);
  EXPECT_TRUE(runner.done());
  EXPECT_EQ(progress.finished.size(), 4u);
  EXPECT_GE(progress.max_running, 1);
  EXPECT_LE(progress.max_running, 2);
  EXPECT_LT(clock.seconds(), 20.0);

  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const auto runs = batchRuns(db, id);
  ASSERT_EQ(runs.size(), 4u);
  std::set<std::string> keys;
  for (const log::RunRecord& r : runs) {
    ASSERT_NO_FATAL_FAILURE(expectTinyRunStored(db, r, id));
    keys.insert(r.meta.params_json + "/" + std::to_string(r.meta.seed));
  }
  EXPECT_EQ(keys.size(), 4u);
  ASSERT_NO_FATAL_FAILURE(expectEveryEventArrives(db, runs));
  ASSERT_NO_FATAL_FAILURE(expectFinishedBatchOfFour(db_path, id));
}

TEST(BatchStatus, ColumnsAddUpToTheRunsWhileSomeAreLive) {
  // 10 runs: 3 solved, 1 skipped, 2 running, 4 not started. BatchInfo::pending (6: no final result yet)
  // holds the live ones too; the table's pending column must not count them twice.
  BatchInfo b;
  b.record.id = "b1";
  b.record.name = "n";
  b.status = "running";
  b.total = 10;
  b.by_status = {{"solved", 3}, {"skipped", 1}, {"running", 2}};
  b.pending = 6;
  const std::string live = formatBatchInfo({b});
  EXPECT_TRUE(std::regex_search(live, std::regex(R"(b1\s+n\s+running\s+10\s+3\s+0\s+0\s+0\s+0\s+1\s+2\s+4\s)")))
      << live;
  // Interrupted: the 'running' rows are stale, to re-run: all 6 are pending.
  b.status = "interrupted";
  const std::string stale = formatBatchInfo({b});
  EXPECT_TRUE(std::regex_search(stale, std::regex(R"(b1\s+n\s+interrupted\s+10\s+3\s+0\s+0\s+0\s+0\s+1\s+0\s+6\s)")))
      << stale;
}

TEST(BatchRunner, CrashedRunIsRecordedWithItsSignalAndTheBatchGoesOn) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const BatchSpec spec = specOf(
      sortingSpec("4", "[1, 2]",
                  std::string("[") + R"({"name":"lazy-dash","settings":{"test_fault":"abort"},"label":"crash"},)" +
                      kTaskOnly + "]"));
  ProgressLog progress;
  BatchRunner runner;
  const std::string id = runner.start(spec, db_path, testOptions(2), progress.callback());
  const BatchResult result = runner.wait();
  EXPECT_EQ(result.status, "finished") << result.error;
  EXPECT_EQ(result.progress.done, 4);
  EXPECT_EQ(result.progress.crashed, 2);
  EXPECT_EQ(result.progress.solved, 2);

  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  int crashed = 0, solved = 0;
  for (const log::RunRecord& r : batchRuns(db, id)) {
    if (r.meta.planner_config_name == "crash") {
      ++crashed;
      EXPECT_EQ(r.status, RunStatus::Crashed);
      EXPECT_EQ(r.summary.exit_signal.value_or(0), SIGABRT);
      EXPECT_NE(r.summary.error.find("SIGABRT"), std::string::npos) << r.summary.error;
    } else {
      ++solved;
      EXPECT_EQ(r.status, RunStatus::Solved) << r.summary.error;
    }
  }
  EXPECT_EQ(crashed, 2);
  EXPECT_EQ(solved, 2);
  int reported = 0;
  for (const FinishedRun& f : progress.finished) reported += f.status == RunStatus::Crashed && f.exit_signal == SIGABRT;
  EXPECT_EQ(reported, 2);
}

TEST(BatchRunner, TimeLimitIsEnforcedOnAPlannerThatIgnoresIt) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const BatchSpec spec = specOf(sortingSpec(
      "4", "[1]", R"([{"name":"lazy-dash","settings":{"test_fault":"ignore-deadline"},"label":"hang"}])", 1.0));
  BatchRunner runner;
  const Stopwatch clock;
  const std::string id = runner.start(spec, db_path, testOptions(1));
  const BatchResult result = runner.wait();
  const double took = clock.seconds();
  EXPECT_EQ(result.status, "finished") << result.error;
  EXPECT_EQ(result.progress.timeouts, 1);
  EXPECT_LT(took, 6.0) << "a 1 s limit must end the run within a few seconds";
  EXPECT_GT(took, 1.0);

  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const auto runs = batchRuns(db, id);
  ASSERT_EQ(runs.size(), 1u);
  EXPECT_EQ(runs[0].status, RunStatus::Timeout);
  EXPECT_NE(runs[0].summary.error.find("time limit"), std::string::npos) << runs[0].summary.error;
  EXPECT_FALSE(runs[0].summary.exit_signal.has_value());
}

TEST(BatchRunner, CancelStopsTheWorkersAndRecordsTheirRunsCancelled) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const BatchSpec spec = specOf(sortingSpec(
      "4", "[1, 2, 3, 4]", R"([{"name":"lazy-dash","settings":{"test_fault":"ignore-deadline"},"label":"hang"}])", 60));
  BatchRunner runner;
  const std::string id = runner.start(spec, db_path, testOptions(2));
  // Wait until both workers run.
  const Stopwatch clock;
  while (runner.progress().running < 2 && clock.seconds() < 10)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_EQ(runner.progress().running, 2);
  std::this_thread::sleep_for(std::chrono::milliseconds(300));

  // A second runner may not resume a batch whose runner is alive.
  {
    BatchRunner other;
    EXPECT_THROW(other.resume(id, db_path, testOptions(1)), InputError);
  }
  const Stopwatch cancel_clock;
  runner.cancel();
  const BatchResult result = runner.wait();
  EXPECT_LT(cancel_clock.seconds(), 4.0);
  EXPECT_EQ(result.status, "cancelled");
  EXPECT_EQ(result.progress.cancelled, 2);
  EXPECT_EQ(result.progress.done, 0);

  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const auto runs = batchRuns(db, id);
  ASSERT_EQ(runs.size(), 2u);  // the two that never started have no row
  for (const auto& r : runs) EXPECT_EQ(r.status, RunStatus::Cancelled) << r.summary.error;
  const auto info = listBatchInfo(db_path, id);
  EXPECT_EQ(info[0].status, "cancelled");
  EXPECT_EQ(info[0].pending, 4);  // cancelled runs are run again by a resume
}

TEST(BatchRunner, ResumeReplacesAStaleRunningRowAndItsPartialEvents) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const BatchSpec spec = specOf(sortingSpec("[4, 6]", "[1]", std::string("[") + kTaskOnly + "]"));
  const std::vector<RunSpec> runs = expandRuns(spec);
  const std::string id = "stale-batch";
  std::string stale_uuid;
  {
    // What a runner killed mid-run leaves: the batch 'running', run 0 'running' with some events,
    // run 1 never started, and a row no key refers to.
    log::ResultsDb db(db_path);
    db.putBatch(log::BatchRecord{.id = id, .name = "test", .spec_json = spec.json, .status = "running"});
    BatchStore store(db_path);
    store.addRuns(id, runs);
    stale_uuid = "00000000-0000-4000-8000-000000000001";
    store.assignUuid(id, runs[0].key, stale_uuid);
    db.beginRun(log::RunMetadata{.uuid = stale_uuid,
                                 .batch_id = id,
                                 .family = "sorting",
                                 .params_json = runs[0].paramsJson(),
                                 .seed = 1,
                                 .planner = "lazy-dash"});
    auto recorder = db.recorder(stale_uuid);
    log::EventEmitter emitter(recorder.get());
    for (std::uint32_t i = 0; i < 50; ++i) emitter.vertex(log::Layer::Task, i, "partial");
    db.beginRun(log::RunMetadata{.uuid = "00000000-0000-4000-8000-000000000002",
                                 .batch_id = id,
                                 .family = "sorting",
                                 .params_json = runs[1].paramsJson(),
                                 .seed = 1,
                                 .planner = "lazy-dash"});
    db.flush();
  }
  {
    const auto info = listBatchInfo(db_path, id);
    EXPECT_EQ(info[0].status, "interrupted");  // 'running' without a live runner
    EXPECT_EQ(info[0].pending, 2);
  }
  BatchRunner runner;
  runner.resume(id, db_path, testOptions(2));
  const BatchResult result = runner.wait();
  EXPECT_EQ(result.status, "finished") << result.error;
  EXPECT_EQ(result.progress.solved, 2);

  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  const auto stored_runs = batchRuns(db, id);
  ASSERT_EQ(stored_runs.size(), 2u);  // the stale row and the orphan are gone: one row per key
  for (const auto& r : stored_runs) {
    EXPECT_EQ(r.status, RunStatus::Solved);
    EXPECT_NE(r.meta.uuid, stale_uuid);
  }
  EXPECT_FALSE(db.getRun(stale_uuid).has_value());
  EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_events WHERE label = 'partial'"), 0);
  EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_events WHERE run_id NOT IN (SELECT id FROM dash_runs)"), 0);
  const BatchStore store(db_path, log::OpenMode::ReadOnly);
  for (const StoredRun& s : store.runs(id)) EXPECT_TRUE(s.complete());
  EXPECT_EQ(listBatchInfo(db_path, id)[0].status, "finished");
}

TEST(BatchRunner, RunnerKilledWithSigkillThenResumedLosesAndDuplicatesNothing) {
  TempDir dir;
  const std::string db_path = dir.file("results.db");
  const std::string spec_path =
      dir.write("spec.json", sortingSpec("[4, 6, 8, 10, 12, 14]", "[1, 2]", std::string("[") + kTaskOnly + "]"));
  const std::string id = "killed-batch";
  test::ChildProcess cli(test::dashbenchCommand({"batch", "run", spec_path, "--db", db_path, "--workers", "2", "--id", id}),
                         {.output = dir.file("run.log")});
  ASSERT_GT(cli.pid(), 0);

  // Kill it once a few runs are finished.
  std::int64_t finished_at_kill = 0, running_at_kill = 0;
  const Stopwatch clock;
  while (clock.seconds() < 30) {
    try {
      const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
      finished_at_kill = scalar(db, "SELECT COUNT(*) FROM dash_runs WHERE status != 'running'");
      running_at_kill = scalar(db, "SELECT COUNT(*) FROM dash_runs WHERE status = 'running'");
      if (finished_at_kill >= 3) break;
    } catch (const std::exception&) {
      // Not created yet, or being migrated.
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ASSERT_TRUE(cli.kill(SIGKILL));
  EXPECT_EQ(cli.wait(), 128 + SIGKILL);
  ASSERT_GE(finished_at_kill, 3);
  ASSERT_LT(finished_at_kill, 12) << "the batch ended before the kill; the test needs longer runs";

  // What survived the kill.
  std::map<std::string, std::string> complete_before;  // key -> uuid
  {
    const BatchStore store(db_path, log::OpenMode::ReadOnly);
    const auto stored = store.runs(id);
    ASSERT_EQ(stored.size(), 12u);
    for (const StoredRun& s : stored) {
      if (s.complete()) complete_before[s.spec.key] = s.run_uuid;
    }
    EXPECT_GE(complete_before.size(), 3u);
    EXPECT_EQ(listBatchInfo(db_path, id)[0].status, "interrupted");
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // children die with their parent (PDEATHSIG)

  test::ChildProcess resume(test::dashbenchCommand({"batch", "resume", "--db", db_path, id, "--workers", "2"}),
                            {.output = dir.file("resume.log")});
  EXPECT_EQ(resume.wait(), 0) << resume.log();

  const log::ResultsDb db(db_path, log::OpenMode::ReadOnly);
  EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_runs WHERE batch_id = ?", {id}), 12);  // one row per key
  EXPECT_EQ(scalar(db, "SELECT COUNT(*) FROM dash_runs WHERE batch_id = ? AND status = 'solved'", {id}), 12);
  for (const char* table : {"dash_events", "dash_constraints", "dash_phases", "dash_counters", "dash_progress"}) {
    EXPECT_EQ(
        scalar(db, std::string("SELECT COUNT(*) FROM ") + table + " WHERE run_id NOT IN (SELECT id FROM dash_runs)"), 0)
        << table;
  }
  const BatchStore store(db_path, log::OpenMode::ReadOnly);
  std::set<std::string> uuids;
  for (const StoredRun& s : store.runs(id)) {
    EXPECT_TRUE(s.complete()) << s.spec.key;
    uuids.insert(s.run_uuid);
    const auto before = complete_before.find(s.spec.key);
    if (before != complete_before.end()) {
      EXPECT_EQ(s.run_uuid, before->second) << "a complete run was run again: " << s.spec.key;
      EXPECT_EQ(s.attempts, 1);
    }
  }
  EXPECT_EQ(uuids.size(), 12u);
  EXPECT_EQ(listBatchInfo(db_path, id)[0].status, "finished");
  std::printf("[ info     ] killed with %lld finished and %lld running\n", static_cast<long long>(finished_at_kill),
              static_cast<long long>(running_at_kill));
}

TEST(ProgressPrinter, FormatsTheBarAndLines) {
  BatchProgress p;
  p.total = 40;
  p.done = 12;
  p.failed = 2;
  p.crashed = 1;
  p.running = 2;
  p.remaining = 28;
  p.eta = 80;
  const std::string bar = ProgressPrinter::formatBar(p, 10);
  EXPECT_EQ(bar.substr(0, 12), "[###.......]");
  EXPECT_NE(bar.find("12/40 done"), std::string::npos) << bar;
  EXPECT_NE(bar.find("2 failed"), std::string::npos) << bar;
  EXPECT_NE(bar.find("2 running"), std::string::npos) << bar;
  EXPECT_NE(bar.find("28 left"), std::string::npos) << bar;
  EXPECT_NE(bar.find("ETA 1m20s"), std::string::npos) << bar;
  EXPECT_NE(bar.find("1 crashed"), std::string::npos) << bar;
  const std::string line =
      ProgressPrinter::formatLine(p, FinishedRun{.key = "sorting/robots=4,objects=8/seed=1/lazy-dash",
                                                 .status = RunStatus::Crashed,
                                                 .seconds = 0.5,
                                                 .error = "killed by SIGABRT (Aborted)"});
  EXPECT_NE(line.find("[12/40] crashed"), std::string::npos) << line;
  EXPECT_NE(line.find("sorting/robots=4,objects=8/seed=1/lazy-dash"), std::string::npos) << line;
  EXPECT_NE(line.find("SIGABRT"), std::string::npos) << line;
  EXPECT_EQ(ProgressPrinter::formatDuration(3725), "1h02m");
  EXPECT_EQ(ProgressPrinter::formatDuration(12), "12s");
}

TEST(ProgressPrinter, ShowsTheStepsOfTheRunsThatAreScheduling) {
  BatchProgress p;
  p.total = 4;
  p.running = 2;
  p.remaining = 4;
  const std::string key = "sorting/robots=32,objects=128/seed=9/lazy-dash";
  p.active.push_back({key, "u1", 75.0, log::ProgressEvent{log::Phase::ConflictResolution, 37, 146, 4.25, "ur5e_3, ur5e_7"}});
  p.active.push_back({"other", "u2", 3.0, std::nullopt});  // no progress reported yet
  EXPECT_NE(ProgressPrinter::formatBar(p).find("| steps 37/146"), std::string::npos) << ProgressPrinter::formatBar(p);
  EXPECT_EQ(ProgressPrinter::formatWork(p.active[0]), "steps 37/146 (ur5e_3, ur5e_7) 4.2 steps/s");
  EXPECT_EQ(ProgressPrinter::formatWork(p.active[1]), "");
  EXPECT_EQ(ProgressPrinter::formatActiveLine(p.active[0]),
            "[running]  " + key + "  steps 37/146 (ur5e_3, ur5e_7) 4.2 steps/s  1m15s");

  // Lines mode: a line per scheduling run, again once 2 s of the batch passed; none once its work ended.
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  ASSERT_NE(out, nullptr);
  ProgressPrinter printer(out, ProgressPrinter::Mode::kLines);
  for (double elapsed : {10.0, 11.0, 12.5}) {
    p.elapsed = elapsed;
    printer(p);
  }
  p.active[0].work->current.clear();
  p.elapsed = 20.0;
  printer(p);
  std::fclose(out);
  const std::string lines(text, size);
  std::free(text);
  std::size_t count = 0;
  for (std::size_t at = lines.find("[running]"); at != std::string::npos; at = lines.find("[running]", at + 1)) ++count;
  EXPECT_EQ(count, 2u) << lines;
  EXPECT_EQ(lines.find("other"), std::string::npos) << lines;
  // The bar leaves out a run whose work ended.
  EXPECT_EQ(ProgressPrinter::formatBar(p).find("steps"), std::string::npos);
}

TEST(ProgressPrinter, TheEtaCountsDownWhileALongRunWorksAndIsReestimatedWhenARunEnds) {
  SteadyEta eta;
  BatchProgress p;
  p.total = 4;
  p.done = 1;
  p.remaining = 3;
  p.elapsed = 10;
  p.eta = 30;  // the runner's: 10 s per finished run, 3 left
  EXPECT_DOUBLE_EQ(eta(p), 30);
  p.elapsed = 20;
  p.eta = 60;  // the runner's grows while nothing ends (issue 41: 23 s left became 119 s)
  EXPECT_DOUBLE_EQ(eta(p), 20);
  p.elapsed = 45;
  p.eta = 135;
  EXPECT_LT(eta(p), 0) << "past its estimate the ETA is unknown, not 0 s and not the runner's larger one";
  p.done = 2;
  p.remaining = 2;
  p.elapsed = 50;
  p.eta = 50;
  EXPECT_DOUBLE_EQ(eta(p), 50);
}

TEST(ProgressPrinter, ALongRunWithoutProgressEventsGetsLinesAndTheBarNamesIt) {
  BatchProgress p;
  p.total = 2;
  p.running = 1;
  p.remaining = 2;
  const std::string key = "sorting/robots=4,objects=8/seed=1/dash";
  p.active.push_back({key, "u1", 0.0, std::nullopt});  // a DaSH construction: no progress events
  char* text = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&text, &size);
  ASSERT_NE(out, nullptr);
  ProgressPrinter printer(out, ProgressPrinter::Mode::kLines);
  for (double elapsed : {5.0, 12.0, 18.0, 26.0}) {
    p.elapsed = elapsed;
    p.active[0].seconds = elapsed;
    printer(p);
  }
  std::fclose(out);
  const std::string lines(text, size);
  std::free(text);
  EXPECT_EQ(lines, "[running]  " + key + "  12s\n[running]  " + key + "  26s\n");
  EXPECT_NE(ProgressPrinter::formatBar(p).find("| " + key + " 26s"), std::string::npos) << ProgressPrinter::formatBar(p);
  p.active[0].seconds = 2.0;  // a quick run is not named
  EXPECT_EQ(ProgressPrinter::formatBar(p).find(key), std::string::npos) << ProgressPrinter::formatBar(p);
}

TEST(ProgressPrinter, ALongRunWithoutProgressEventsIsNamedWithThePhaseItIsIn) {
  BatchProgress p;
  p.total = 1;
  p.running = 1;
  p.remaining = 1;
  const std::string key = "sorting/robots=4,objects=8/seed=1/dash";
  p.active.push_back({key, "u1", 26.0, std::nullopt, log::Phase::MotionConstruction});
  EXPECT_EQ(ProgressPrinter::formatActiveLine(p.active[0]), "[running]  " + key + "  in motion construction  26s");
  EXPECT_NE(ProgressPrinter::formatBar(p).find("| " + key + " in motion construction 26s"), std::string::npos)
      << ProgressPrinter::formatBar(p);
  p.active[0].phase = log::Phase::Other;  // bookkeeping between phases: no phase named
  EXPECT_EQ(ProgressPrinter::formatActiveLine(p.active[0]), "[running]  " + key + "  26s");
}

}  // namespace
}  // namespace dash::batch
