#include <gtest/gtest.h>
#include <sqlite3.h>

#include <atomic>
#include <thread>

#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

std::int64_t count(const ResultsDb& db, const std::string& sql, const std::vector<SqlValue>& params = {}) {
  const SqlRows rows = db.select(sql, params);
  const SqlValue& v = rows.rows.at(0).at(0);
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : 0;
}

TEST(Recorder, StoredEventsAndSizesEqualWhatWasEmitted) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  MemorySink mirror;
  const std::string uuid = testing::recordRun(db, testing::sampleMeta(), 60, &mirror);
  const auto run = db.getRun(uuid);
  ASSERT_TRUE(run.has_value());
  ASSERT_TRUE(run->summary.sizes.has_value());
  const std::int64_t id = run->id;

  for (int l = 0; l < kLayerCount; ++l) {
    const Layer layer = static_cast<Layer>(l);
    for (ElementKind kind : {ElementKind::Vertex, ElementKind::Hyperarc}) {
      const std::int64_t emitted = mirror.count(layer, kind);
      const std::int64_t stored =
          count(db, "SELECT SUM(CASE change WHEN 'added' THEN 1 ELSE -1 END) FROM dash_events WHERE run_id = ? AND layer = ? AND kind = ?",
                {id, std::string(toString(layer)), std::string(toString(kind))});
      EXPECT_EQ(stored, emitted) << toString(layer) << " " << toString(kind);
      const auto& sizes = kind == ElementKind::Vertex ? run->summary.sizes->vertices : run->summary.sizes->hyperarcs;
      EXPECT_EQ(sizes[l], emitted) << toString(layer) << " " << toString(kind);
    }
  }
  EXPECT_GT(mirror.count(Layer::Motion, ElementKind::Hyperarc), 0);
  EXPECT_EQ(count(db, "SELECT COUNT(*) FROM dash_events WHERE run_id = ? AND layer = 'task' AND arc_type = 'pick'", {id}),
            mirror.countHyperarcs(Layer::Task, "pick"));
  for (int k = 0; k < kConstraintKindCount; ++k) {
    EXPECT_EQ((*run->summary.constraints)[k],
              mirror.countConstraints(static_cast<ConstraintKind>(k), ConstraintAction::Created));
  }
  EXPECT_EQ(run->summary.task_space_expansions, mirror.countTaskSpaceExpansions());
  EXPECT_EQ(run->summary.collision_checks_eager, mirror.counter("collision_checks_eager"));
  EXPECT_EQ(run->summary.collision_checks_lazy, mirror.counter("collision_checks_lazy"));
  EXPECT_EQ(run->collision_checks, mirror.counter("collision_checks_eager") + mirror.counter("collision_checks_lazy"));
  EXPECT_EQ(run->summary.roadmap_vertices, mirror.counter("roadmap_vertices"));
  EXPECT_EQ(run->summary.iterations, 60);
  for (int p = 0; p < kPhaseCount; ++p) {
    EXPECT_NEAR((*run->summary.phase_seconds)[p], mirror.phaseSeconds(static_cast<Phase>(p)), 1e-12);
  }
  // Every event but phase starts is one row.
  std::int64_t phase_starts = 0;
  for (const Event& e : mirror.events()) {
    const auto* p = std::get_if<PhaseEvent>(&e.payload);
    phase_starts += p && p->boundary == PhaseBoundary::Start;
  }
  EXPECT_EQ(run->event_count, static_cast<std::int64_t>(mirror.size()) - phase_starts);
  EXPECT_EQ(count(db, "SELECT COUNT(*) FROM dash_timeline WHERE run_id = ?", {id}), run->event_count);
  EXPECT_EQ(run->status, RunStatus::Solved);
  EXPECT_EQ(run->summary.makespan, 12.5);
  EXPECT_FALSE(run->end_time.empty());
}

TEST(Recorder, ProgressSnapshotsGrowAndEndAtTheFinalSizes) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  const std::string uuid = db.beginRun(testing::sampleMeta());
  MemorySink mirror;
  {
    auto recorder = db.recorder(uuid, RecorderOptions{.progress_interval = 0.0});
    TeeSink tee({recorder.get(), &mirror});
    EventEmitter em(&tee);
    testing::emitScriptedRun(em, 20);
    db.finishRun(uuid, RunSummary{.status = RunStatus::Timeout});
  }
  const SqlRows rows = db.select("SELECT task_vertices, motion_vertices FROM progress WHERE runid = ? ORDER BY time",
                                 {db.getRun(uuid)->id});
  ASSERT_GT(rows.rows.size(), 20u);
  std::int64_t previous = 0;
  for (const auto& row : rows.rows) {
    EXPECT_GE(std::get<std::int64_t>(row[0]), previous);
    previous = std::get<std::int64_t>(row[0]);
  }
  EXPECT_EQ(previous, mirror.count(Layer::Task, ElementKind::Vertex));
  EXPECT_EQ(std::get<std::int64_t>(rows.rows.back()[1]), mirror.count(Layer::Motion, ElementKind::Vertex));
}

TEST(Recorder, ConflictResolutionProgressGoesIntoTheSnapshots) {
  // A build of 5 steps reported step by step (closer together than the snapshot interval), then its
  // end: every report is a snapshot, the sizes beside it, and the run's last snapshot keeps the last.
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  const std::string uuid = db.beginRun(testing::sampleMeta());
  {
    auto recorder = db.recorder(uuid, RecorderOptions{.progress_interval = 0.05});
    recorder->onEvent(Event{0.5, 3, RepresentationEvent{.layer = Layer::Motion, .kind = ElementKind::Vertex, .id = 1}});
    for (int k = 0; k < 5; ++k) {
      recorder->onEvent(Event{1.0 + 0.001 * k, 3,
                              ProgressEvent{Phase::ConflictResolution, k, 5, 2.0 * k, "ur5e_" + std::to_string(k)}});
    }
    recorder->onEvent(Event{1.01, 3, ProgressEvent{Phase::ConflictResolution, 5, 5, 10.0, ""}});
    db.finishRun(uuid, RunSummary{.status = RunStatus::Solved, .total_time = 2.0});
  }
  const std::int64_t id = db.getRun(uuid)->id;
  const SqlRows rows = db.select("SELECT t, progress_phase, progress_done, progress_total, progress_current, "
                                 "motion_vertices, iteration FROM dash_progress WHERE run_id = ? AND progress_phase IS "
                                 "NOT NULL ORDER BY t",
                                 {id});
  ASSERT_EQ(rows.rows.size(), 7u);  // 5 steps, the end, the run's last snapshot
  for (int k = 0; k < 5; ++k) {
    const auto& row = rows.rows[static_cast<std::size_t>(k)];
    EXPECT_EQ(row[1], SqlValue(std::string("conflict_resolution")));
    EXPECT_EQ(row[2], SqlValue(std::int64_t{k}));
    EXPECT_EQ(row[3], SqlValue(std::int64_t{5}));
    EXPECT_EQ(row[4], SqlValue("ur5e_" + std::to_string(k)));
    EXPECT_EQ(row[5], SqlValue(std::int64_t{1}));
    EXPECT_EQ(row[6], SqlValue(std::int64_t{3}));
  }
  for (const std::size_t i : {5u, 6u}) {
    EXPECT_EQ(rows.rows[i][2], SqlValue(std::int64_t{5}));
    EXPECT_EQ(rows.rows[i][3], SqlValue(std::int64_t{5}));
    EXPECT_EQ(rows.rows[i][4], SqlValue());  // ended: no current step
  }
  EXPECT_EQ(rows.rows[6][0], SqlValue(2.0));
  // Before the first progress event a snapshot has none.
  EXPECT_EQ(db.select("SELECT COUNT(*) FROM dash_progress WHERE run_id = ? AND progress_phase IS NULL", {id}).rows[0][0],
            SqlValue(std::int64_t{1}));
}

TEST(Recorder, ProgressSnapshotsFollowALongPhase) {
  // One 2 s phase that adds a vertex every 10 ms (DaSH's motion construction): the snapshots must
  // show the growth during the phase, not only its end.
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  const std::string uuid = db.beginRun(testing::sampleMeta());
  {
    auto recorder = db.recorder(uuid, RecorderOptions{.progress_interval = 0.05});
    // Event times start at kStart so that finishRun's last snapshot (at the wall-clock time since
    // beginRun, a fraction of a second here) stays out of the window checked below.
    constexpr double kStart = 1000.0;
    recorder->onEvent(Event{kStart, 0, PhaseEvent{.phase = Phase::MotionConstruction}});
    for (int k = 0; k < 200; ++k) {
      recorder->onEvent(Event{kStart + 0.01 * k, 0, RepresentationEvent{.layer = Layer::Motion, .kind = ElementKind::Vertex,
                                                                         .id = static_cast<std::uint32_t>(k)}});
    }
    recorder->onEvent(Event{kStart + 2.0, 0, PhaseEvent{Phase::MotionConstruction, PhaseBoundary::End, 2.0}});
    db.finishRun(uuid, RunSummary{.status = RunStatus::Solved});
  }
  const SqlRows rows = db.select("SELECT t, motion_vertices FROM dash_progress WHERE run_id = ? AND t >= 1000 AND t < 1001.99 ORDER BY t",
                                 {db.getRun(uuid)->id});
  ASSERT_GE(rows.rows.size(), 30u);
  ASSERT_LE(rows.rows.size(), 41u);  // at most one per interval
  std::int64_t previous = -1;
  for (const auto& row : rows.rows) {
    const std::int64_t v = std::get<std::int64_t>(row[1]);
    EXPECT_GT(v, previous);
    previous = v;
  }
  EXPECT_GT(previous, 150);
}

TEST(Recorder, ReportedFiguresWinOverDerivedOnes) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  const std::string uuid = db.beginRun(testing::sampleMeta());
  RepresentationSizes reported;
  reported.vertices[0] = 99;
  db.finishRun(uuid, RunSummary{.status = RunStatus::Infeasible, .total_time = 4.0, .sizes = reported,
                                .peak_memory_mb = 123.0, .error = "no plan exists"});
  const auto run = db.getRun(uuid);
  EXPECT_EQ(run->summary.sizes->vertices[0], 99);
  EXPECT_EQ(run->summary.total_time, 4.0);
  EXPECT_EQ(run->summary.peak_memory_mb, 123.0);
  EXPECT_EQ(run->summary.error, "no plan exists");
  EXPECT_EQ(run->status, RunStatus::Infeasible);
  EXPECT_FALSE(run->collision_checks.has_value());  // nothing emitted, nothing reported: NULL
}

TEST(Recorder, BadCallsAreInputErrors) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  EXPECT_THROW(db.finishRun("no-such-run", {}), InputError);
  EXPECT_THROW(db.beginRun(testing::sampleMeta("sorting", "[1,2]")), InputError);
  EXPECT_THROW(db.beginRun(testing::sampleMeta("sorting", R"({"bad name":1})")), InputError);
  EXPECT_THROW(db.beginRun(testing::sampleMeta("")), InputError);
  const std::string uuid = db.beginRun(testing::sampleMeta());
  EXPECT_THROW(db.finishRun(uuid, RunSummary{.status = RunStatus::Running}), InputError);
  db.finishRun(uuid, {});
  EXPECT_THROW(db.finishRun(uuid, {}), InputError);
  RunMetadata again = testing::sampleMeta();
  again.uuid = uuid;
  EXPECT_THROW(db.beginRun(again), InputError);
  ResultsDb ro(dir.file("r.db"), OpenMode::ReadOnly);
  EXPECT_THROW(ro.beginRun(testing::sampleMeta()), InputError);
}

TEST(Recorder, EventsAfterFinishAreDropped) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  const std::string uuid = db.beginRun(testing::sampleMeta());
  auto recorder = db.recorder(uuid);
  EventEmitter em(recorder.get());
  em.vertex(Layer::Task, 0);
  db.finishRun(uuid, {});
  em.vertex(Layer::Task, 1);
  EXPECT_EQ(recorder->acceptedEvents(), 1);
  EXPECT_EQ(db.getRun(uuid)->event_count, 1);
}

TEST(Recorder, SeveralThreadsShareOneRecorder) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"), OpenMode::ReadWrite, DbOptions{.batch_events = 100});
  const std::string uuid = db.beginRun(testing::sampleMeta());
  auto recorder = db.recorder(uuid);
  constexpr int kThreads = 4, kPerThread = 2000;
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t) {
    threads.emplace_back([&, t] {
      EventEmitter em(recorder.get());  // one emitter per thread, one sink
      for (int i = 0; i < kPerThread; ++i) em.vertex(Layer::Motion, static_cast<std::uint32_t>(t * kPerThread + i));
    });
  }
  for (auto& th : threads) th.join();
  db.finishRun(uuid, {});
  EXPECT_EQ(db.getRun(uuid)->summary.sizes->vertices[static_cast<int>(Layer::Motion)], kThreads * kPerThread);
}

TEST(Recorder, AFinishIsNotHeldUpByAnotherRunStillRecording) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"), OpenMode::ReadWrite, DbOptions{.batch_events = 16});
  const std::string busy_run = db.beginRun(testing::sampleMeta());
  const std::string quick_run = db.beginRun(testing::sampleMeta());
  auto busy_recorder = db.recorder(busy_run);
  auto quick_recorder = db.recorder(quick_run);
  std::atomic<bool> stop{false};
  std::thread busy([&] {
    EventEmitter em(busy_recorder.get());
    for (std::uint32_t i = 0; !stop.load(); ++i) em.vertex(Layer::Motion, i);
  });
  EventEmitter em(quick_recorder.get());
  testing::emitScriptedRun(em, 10);
  db.finishRun(quick_run, {});  // returns while the other run keeps the writer busy
  EXPECT_EQ(db.getRun(quick_run)->status, RunStatus::Solved);
  stop = true;
  busy.join();
  db.finishRun(busy_run, {});
  const auto busy_record = db.getRun(busy_run);
  EXPECT_EQ(busy_record->event_count, busy_recorder->acceptedEvents());
  EXPECT_EQ(busy_record->summary.sizes->vertices[static_cast<int>(Layer::Motion)], busy_recorder->acceptedEvents());
}

TEST(Recorder, ReadersSeeRunsWhileTheWriterWrites) {
  testing::TempDir dir;
  const std::string path = dir.file("r.db");
  ResultsDb writer(path);
  const std::string uuid = writer.beginRun(testing::sampleMeta());
  auto recorder = writer.recorder(uuid);
  EventEmitter em(recorder.get());
  em.vertex(Layer::Task, 0);  // inside an open batched transaction
  {
    ResultsDb reader(path, OpenMode::ReadOnly);
    const auto seen = reader.getRun(uuid);
    ASSERT_TRUE(seen.has_value());
    EXPECT_EQ(seen->status, RunStatus::Running);
  }
  writer.finishRun(uuid, {});
  ResultsDb reader(path, OpenMode::ReadOnly);
  EXPECT_EQ(reader.getRun(uuid)->status, RunStatus::Solved);
  EXPECT_EQ(reader.info().runs_by_status.at("solved"), 1);
}

TEST(Recorder, MarkInterruptedClosesRunsOfDeadProcessesOnly) {
  testing::TempDir dir;
  const std::string path = dir.file("r.db");
  std::string orphan;
  {
    ResultsDb first(path);
    orphan = first.beginRun(testing::sampleMeta());
    auto recorder = first.recorder(orphan);
    EventEmitter em(recorder.get());
    testing::emitScriptedRun(em, 5);
  }  // closed without finishing, as a killed process would leave it
  ResultsDb db(path);
  const std::string mine = db.beginRun(testing::sampleMeta());
  EXPECT_EQ(db.markInterrupted(), 1);
  const auto closed = db.getRun(orphan);
  EXPECT_EQ(closed->status, RunStatus::Crashed);
  EXPECT_NE(closed->summary.error.find("interrupted"), std::string::npos);
  EXPECT_GT(closed->summary.sizes->vertices[0], 0);  // derived from the events it left
  EXPECT_EQ(db.getRun(mine)->status, RunStatus::Running);
  EXPECT_EQ(db.markInterrupted(), 0);
}

// Representation events go in by kRowsPerInsert (64) at a time, the rest one by one: 200 of them
// exercise both. Every field comes back as emitted, through the dash_events view.
TEST(Recorder, EveryRepresentationFieldIsStoredAsEmitted) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  const std::string uuid = db.beginRun(testing::sampleMeta());
  MemorySink mirror;
  {
    auto recorder = db.recorder(uuid);
    TeeSink tee({recorder.get(), &mirror});
    EventEmitter em(&tee);
    const char* types[] = {"pick", "place", "handover", "transition"};
    for (std::uint32_t i = 0; i < 200; ++i) {
      em.setIteration(static_cast<int>(i / 7));
      const Layer layer = static_cast<Layer>(i % kLayerCount);
      if (i % 3 == 0) {
        em.vertex(layer, i, i % 2 ? "R" + std::to_string(i) + "+O\xc3\xa9 \"q\"" : "");
      } else if (i % 3 == 1) {
        std::vector<std::uint32_t> tail(i % 5);
        for (std::uint32_t k = 0; k < tail.size(); ++k) tail[k] = 4'000'000'000u + k;
        em.hyperarc(layer, types[i % 4], i, {i, i + 1}, tail, i % 2 ? "" : "arc " + std::to_string(i));
      } else {
        em.removed(layer, i % 2 ? ElementKind::Vertex : ElementKind::Hyperarc, i - 1);
      }
    }
    db.finishRun(uuid, {});
  }
  const SqlRows rows = db.select("SELECT seq, t, iteration, layer, kind, change, arc_type, element_id, head, tail, label "
                                 "FROM dash_events WHERE run_id = ? ORDER BY seq",
                                 {db.getRun(uuid)->id});
  ASSERT_EQ(rows.rows.size(), mirror.size());
  auto ids = [](const std::vector<std::uint32_t>& v) {
    std::string out = "[";
    for (std::size_t k = 0; k < v.size(); ++k) out += (k ? "," : "") + std::to_string(v[k]);
    return out + "]";
  };
  auto text = [](const std::string& s) { return s.empty() ? SqlValue() : SqlValue(s); };
  const std::vector<Event> emitted = mirror.events();
  for (std::size_t i = 0; i < rows.rows.size(); ++i) {
    const Event& e = emitted[i];
    const auto& r = std::get<RepresentationEvent>(e.payload);
    const bool arc = r.kind == ElementKind::Hyperarc;
    const std::vector<SqlValue> expected = {static_cast<std::int64_t>(i), e.t, std::int64_t{e.iteration},
                                            std::string(toString(r.layer)), std::string(toString(r.kind)),
                                            std::string(toString(r.change)), arc ? SqlValue(r.arc_type) : SqlValue(),
                                            static_cast<std::int64_t>(r.id), arc ? SqlValue(ids(r.head)) : SqlValue(),
                                            arc ? SqlValue(ids(r.tail)) : SqlValue(), text(r.label)};
    EXPECT_EQ(rows.rows[i], expected) << "event " << i;
  }
}

// finishRun takes the unset figures from the writer's tally of the run; a run finished by another
// process (markInterrupted) gets them from SQL over its stored events. Both must agree: the same
// events finished both ways, in two copies of one file.
TEST(Recorder, TheWritersTallyEqualsWhatSqlDerivesFromTheStoredEvents) {
  testing::TempDir dir;
  const std::string path = dir.file("r.db"), copy = dir.file("copy.db");
  ResultsDb db(path);
  const std::string uuid = db.beginRun(testing::sampleMeta());
  auto recorder = db.recorder(uuid);
  {
    EventEmitter em(recorder.get());
    testing::emitScriptedRun(em, 40);
  }
  db.flush();
  sqlite3* raw = nullptr;
  ASSERT_EQ(sqlite3_open_v2(path.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(raw, ("VACUUM INTO '" + copy + "'").c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
      << sqlite3_errmsg(raw);
  sqlite3_close(raw);
  db.finishRun(uuid, {});
  ResultsDb other(copy);
  ASSERT_EQ(other.markInterrupted(), 1);

  const RunRecord tallied = *db.getRun(uuid);
  const RunRecord derived = *other.getRun(uuid);
  EXPECT_GT(tallied.event_count, 500);
  EXPECT_EQ(tallied.event_count, derived.event_count);
  EXPECT_EQ(tallied.summary.iterations, derived.summary.iterations);
  EXPECT_EQ(tallied.summary.sizes->vertices, derived.summary.sizes->vertices);
  EXPECT_EQ(tallied.summary.sizes->hyperarcs, derived.summary.sizes->hyperarcs);
  EXPECT_EQ(*tallied.summary.phase_seconds, *derived.summary.phase_seconds);
  EXPECT_EQ(*tallied.summary.constraints, *derived.summary.constraints);
  EXPECT_EQ(tallied.summary.task_space_expansions, derived.summary.task_space_expansions);
  EXPECT_EQ(tallied.summary.collision_checks_eager, derived.summary.collision_checks_eager);
  EXPECT_EQ(tallied.summary.collision_checks_lazy, derived.summary.collision_checks_lazy);
  EXPECT_EQ(tallied.collision_checks, derived.collision_checks);
  EXPECT_EQ(tallied.summary.roadmap_vertices, derived.summary.roadmap_vertices);
  EXPECT_EQ(tallied.summary.roadmap_edges, derived.summary.roadmap_edges);
  // The last progress row (written by finishRun) holds the same sizes and active constraints.
  const std::string last = "SELECT task_vertices, motion_hyperarcs, constraints FROM dash_progress WHERE run_id = ? "
                           "ORDER BY t DESC LIMIT 1";
  EXPECT_EQ(db.select(last, {tallied.id}).rows, other.select(last, {derived.id}).rows);
}

TEST(Recorder, BatchesTagsAndFilters) {
  testing::TempDir dir;
  ResultsDb db(dir.file("r.db"));
  db.putBatch(BatchRecord{.id = "batch-1", .name = "figure 5", .spec_json = R"({"b":1, "a":2})"});
  RunMetadata meta = testing::sampleMeta();
  meta.batch_id = "batch-1";
  const std::string a = testing::recordRun(db, meta, 3);
  const std::string b = testing::recordRun(db, testing::sampleMeta("wall", R"({"walls":2})", "dash"), 3);
  db.setBatchStatus("batch-1", "finished");
  const auto batches = db.listBatches();
  ASSERT_EQ(batches.size(), 1u);
  EXPECT_EQ(batches[0].status, "finished");
  EXPECT_EQ(batches[0].spec_json, R"({"a":2,"b":1})");
  EXPECT_EQ(db.listRuns(RunFilter{.batch_id = "batch-1"}).size(), 1u);
  EXPECT_EQ(db.listRuns(RunFilter{.planner = "dash"}).front().meta.uuid, b);
  EXPECT_EQ(db.listRuns().front().meta.uuid, b);  // newest first
  db.addTag(a, "good");
  db.addTag(a, "figure5");
  db.removeTag(a, "good");
  EXPECT_EQ(db.getRun(a)->tags, std::vector<std::string>{"figure5"});
  EXPECT_EQ(db.getRun(a)->meta.params_json, R"({"objects":4,"robots":2})");
  EXPECT_FALSE(db.listRuns().front().summary.plan_json.size());
}

}  // namespace
}  // namespace dash::log
