#include "tests/log/log_test_util.h"

#include <sqlite3.h>

namespace dash::log::testing {

RunMetadata sampleMeta(const std::string& family, const std::string& params, const std::string& planner,
                       std::uint64_t seed) {
  return RunMetadata{.family = family,
                     .params_json = params,
                     .seed = seed,
                     .planner = planner,
                     .time_limit = 60.0,
                     .code_version = "0.1.0-test",
                     .host = "test-host",
                     .cpu_info = "test cpu"};
}

void emitScriptedRun(EventEmitter& em, int iterations) {
  std::uint32_t next_vertex = 0, next_arc = 0, next_constraint = 0;
  {
    PhaseTimer phase(em, Phase::TaskConstruction);
    for (int k = 0; k < 4; ++k) em.vertex(Layer::Task, next_vertex++, "R" + std::to_string(k));
    em.hyperarc(Layer::Task, "source", next_arc++, {0, 1}, {}, "source");
  }
  for (int it = 1; it <= iterations; ++it) {
    em.setIteration(it);
    {
      PhaseTimer phase(em, Phase::TaskQuery);
      const std::uint32_t v = next_vertex++;
      em.vertex(Layer::Task, v, "R1+O" + std::to_string(it));
      em.hyperarc(Layer::Task, it % 2 ? "pick" : "place", next_arc++, {v}, {v - 1}, "pick O" + std::to_string(it));
      em.vertex(Layer::TaskExtended, static_cast<std::uint32_t>(it), "h" + std::to_string(it));
      em.hyperarc(Layer::TaskExtended, "transition", static_cast<std::uint32_t>(it), {v}, {v - 1, v - 2});
    }
    {
      PhaseTimer phase(em, Phase::TaskConflictDetection);
      if (it % 3 == 0) {
        em.constraint(ConstraintKind::History, ConstraintAction::Created, next_constraint++,
                      "(v_pre=" + std::to_string(it) + ", v_post=" + std::to_string(it + 1) + ")",
                      {static_cast<std::uint32_t>(it), static_cast<std::uint32_t>(it + 1)}, "grasp collides with O2");
      }
      if (it % 5 == 0) {
        em.constraint(ConstraintKind::Frontier, ConstraintAction::Created, next_constraint++, "frontier {3}", {3});
      }
      if (it % 10 == 0) em.constraint(ConstraintKind::Frontier, ConstraintAction::Lifted, next_constraint - 1, "", {3});
      if (it % 25 == 0) em.taskSpaceExpansion(2, "O2", "stable pose 7", "order would reverse");
    }
    {
      PhaseTimer phase(em, Phase::MotionConstruction);
      em.vertex(Layer::Motion, static_cast<std::uint32_t>(2 * it), "q" + std::to_string(it));
      em.vertex(Layer::Motion, static_cast<std::uint32_t>(2 * it + 1));
      em.hyperarc(Layer::Motion, "move", static_cast<std::uint32_t>(it), {static_cast<std::uint32_t>(2 * it + 1)},
                  {static_cast<std::uint32_t>(2 * it)});
      if (it % 7 == 0) em.removed(Layer::Motion, ElementKind::Hyperarc, static_cast<std::uint32_t>(it));
      em.counter("roadmap_vertices", 10 * it);
      em.counter("roadmap_edges", 30 * it);
    }
    {
      PhaseTimer phase(em, Phase::MotionQuery);
      em.vertex(Layer::MotionExtended, static_cast<std::uint32_t>(it));
      em.counter("collision_checks_eager", 100 * it);
      em.counter("collision_checks_lazy", 7 * it);
    }
  }
}

std::string recordRun(ResultsDb& db, const RunMetadata& meta, int iterations, MemorySink* mirror) {
  const std::string uuid = db.beginRun(meta);
  {
    auto recorder = db.recorder(uuid);
    NullSink none;
    TeeSink tee({recorder.get(), mirror ? static_cast<EventSink*>(mirror) : &none});
    EventEmitter emitter(&tee);
    emitScriptedRun(emitter, iterations);
    db.finishRun(uuid, RunSummary{.status = RunStatus::Solved, .makespan = 12.5, .path_length = 3.25});
  }
  return uuid;
}

std::string integrityCheck(const std::string& path) {
  sqlite3* db = nullptr;
  sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  std::string result = "cannot run";
  if (sqlite3_prepare_v2(db, "PRAGMA integrity_check", -1, &st, nullptr) == SQLITE_OK && sqlite3_step(st) == SQLITE_ROW) {
    result = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  }
  sqlite3_finalize(st);
  sqlite3_close(db);
  return result;
}

}  // namespace dash::log::testing
