// The writer thread of a ResultsDb: drains recorders' batches into SQLite, one transaction per
// drain, and keeps each run's running figures (sizes for the progress snapshots, everything
// finishRun would otherwise derive from the stored events).
#include <charconv>
#include <cstdio>

#include "engine/log/results_db_impl.h"

namespace dash::log {
namespace {

// "[1,2,3]": JSON, so SQL can read it with json_each.
void writeIds(const IdView& ids, std::string& out) {
  out.clear();
  out.push_back('[');
  char buffer[16];
  for (std::uint32_t i = 0; i < ids.size(); ++i) {
    if (i != 0) out.push_back(',');
    const auto end = std::to_chars(buffer, buffer + sizeof(buffer), ids[i]).ptr;
    out.append(buffer, end);
  }
  out.push_back(']');
}

constexpr int kEventColumns = 12;  // run_id, seq, t, iteration, layer, kind, change, arc_type, element_id, head, tail, label

void bindEventRow(sql::Statement& st, int first, const ResultsDb::Impl::EventRow& r) {
  st.bind(first, r.run_id).bind(first + 1, r.seq).bind(first + 2, r.t).bind(first + 3, r.iteration);
  st.bind(first + 4, r.layer).bind(first + 5, r.kind).bind(first + 6, r.change);
  if (r.kind == static_cast<int>(ElementKind::Hyperarc)) {
    st.bindStatic(first + 7, r.arc_type).bindStatic(first + 9, r.head).bindStatic(first + 10, r.tail);
  } else {
    st.bindNull(first + 7).bindNull(first + 9).bindNull(first + 10);
  }
  st.bind(first + 8, static_cast<std::int64_t>(r.id));
  if (r.label.empty()) {
    st.bindNull(first + 11);
  } else {
    st.bindStatic(first + 11, r.label);
  }
}

}  // namespace

void ResultsDb::Impl::enqueue(Batch batch) {
  if (batch.events.empty()) return;
  std::unique_lock lock(queue_mutex);
  if (stopping) return;  // the database is closing; its recorders were closed first
  if (!writer.joinable()) writer = std::thread([this] { writerLoop(); });
  queue_changed.wait(lock, [&] { return queued_events < options.max_queued_events || stopping; });
  queued_events += batch.events.events();
  batch.ticket = ++enqueued;
  queue.push_back(std::move(batch));
  queue_changed.notify_all();
}

void ResultsDb::Impl::waitDrained() {
  std::unique_lock lock(queue_mutex);
  const std::uint64_t target = enqueued;
  queue_changed.wait(lock, [&] { return written >= target; });
}

void ResultsDb::Impl::stopWriter() {
  {
    std::lock_guard lock(queue_mutex);
    stopping = true;
    queue_changed.notify_all();
  }
  if (writer.joinable()) writer.join();
}

void ResultsDb::Impl::writerLoop() {
  std::unique_lock lock(queue_mutex);
  while (true) {
    queue_changed.wait(lock, [&] { return stopping || !queue.empty(); });
    if (queue.empty()) return;  // stopping, and everything is written
    std::deque<Batch> work;
    work.swap(queue);
    queued_events = 0;
    lock.unlock();
    queue_changed.notify_all();  // producers waiting for room may go on
    {
      std::lock_guard db_lock(mutex);
      try {
        beginWriteLocked();
        EventView event;
        for (const Batch& batch : work) {
          RunState& state = run_states[batch.run_id];
          if (!state.error.empty()) continue;
          EventBatch::Reader reader(batch.events);
          while (reader.next(event)) writeEventLocked(batch.run_id, state, event);
        }
        flushEventRowsLocked();  // before the batches they point into go
        commitLocked();
      } catch (const std::exception& e) {
        pending_rows = 0;
        rollbackLocked();
        for (const Batch& batch : work) {
          if (run_states[batch.run_id].error.empty()) run_states[batch.run_id].error = e.what();
        }
      }
    }
    lock.lock();
    written = work.back().ticket;
    queue_changed.notify_all();
  }
}

void ResultsDb::Impl::writeEventLocked(std::int64_t run_id, RunState& s, const EventView& e) {
  const std::int64_t seq = s.seq++;
  RunFigures& f = s.figures;
  ++f.events;
  f.max_iteration = std::max<std::int64_t>(f.max_iteration, e.iteration);
  f.last_t = std::max(f.last_t, e.t);
  switch (e.type) {
    case 0:  // representation: buffered for insert_events
      writeRepresentationLocked(run_id, seq, s, e);
      break;
    case 1:
      writeConstraintLocked(run_id, seq, s, e);
      break;
    case 2: {
      ++f.expansions;
      sql::Statement& st = insert_expansion;
      st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration).bind(5, static_cast<std::int64_t>(e.id));
      st.bindStatic(6, e.object_label).bindStatic(7, e.added).bindStatic(8, e.reason);
      st.runKeepingBindings();
      break;
    }
    case 3: {
      f.phases[static_cast<int>(e.phase)] += e.duration;
      sql::Statement& st = insert_phase;
      st.bind(1, run_id).bind(2, seq).bind(3, e.iteration).bindStatic(4, toString(e.phase));
      st.bind(5, e.t - e.duration).bind(6, e.t).bind(7, e.duration);
      st.runKeepingBindings();
      if (e.t - s.last_progress_t >= s.progress_interval) writeProgressLocked(run_id, s, e.t, e.iteration);
      break;
    }
    case 5: {  // progress: no table of its own, the next snapshots carry it
      s.work_phase = static_cast<int>(e.phase);
      s.work_done = e.done;
      s.work_total = e.total;
      s.work_rate = e.rate;
      s.work_current.assign(e.current);
      // Every one (their producers emit them seldom), so that a phase's last one is always stored.
      writeProgressLocked(run_id, s, e.t, e.iteration);
      break;
    }
    default:  // 4, counter
      writeCounterLocked(run_id, seq, s, e);
      break;
  }
}

void ResultsDb::Impl::writeRepresentationLocked(std::int64_t run_id, std::int64_t seq, RunState& s,
                                                const EventView& e) {
  RunFigures& f = s.figures;
  const int layer = static_cast<int>(e.layer);
  auto& count = e.kind == ElementKind::Vertex ? f.sizes.vertices[layer] : f.sizes.hyperarcs[layer];
  count += e.change == ElementChange::Added ? 1 : -1;
  EventRow& row = event_rows[static_cast<std::size_t>(pending_rows++)];
  row.run_id = run_id;
  row.seq = seq;
  row.t = e.t;
  row.iteration = e.iteration;
  row.layer = layer;
  row.kind = static_cast<int>(e.kind);
  row.change = static_cast<int>(e.change);
  row.id = e.id;
  row.arc_type = e.arc_type;
  row.label = e.label;
  if (e.kind == ElementKind::Hyperarc) {
    writeIds(e.head, row.head);
    writeIds(e.tail, row.tail);
  }
  if (pending_rows == kRowsPerInsert) flushEventRowsLocked();
  // Within a long phase too (DaSH builds H_M for many seconds in one phase), not only at its end.
  if (e.t - s.last_progress_t >= s.progress_interval) writeProgressLocked(run_id, s, e.t, e.iteration);
}

void ResultsDb::Impl::writeConstraintLocked(std::int64_t run_id, std::int64_t seq, RunState& s, const EventView& e) {
  RunFigures& f = s.figures;
  f.active_constraints += e.action == ConstraintAction::Created ? 1 : -1;
  if (e.action == ConstraintAction::Created) ++f.constraints[static_cast<int>(e.constraint_kind)];
  writeIds(e.vertices, s.ids_buffer);
  sql::Statement& st = insert_constraint;
  st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration);
  st.bindStatic(5, toString(e.constraint_kind)).bindStatic(6, toString(e.action));
  st.bind(7, static_cast<std::int64_t>(e.id)).bindStatic(8, e.content).bindStatic(9, s.ids_buffer);
  st.bindOrNull(10, e.conflict);
  st.runKeepingBindings();
}

void ResultsDb::Impl::writeCounterLocked(std::int64_t run_id, std::int64_t seq, RunState& s, const EventView& e) {
  RunFigures& f = s.figures;
  if (e.name == "roadmap_vertices") s.roadmap_vertices = e.value;
  if (e.name == "roadmap_edges") s.roadmap_edges = e.value;
  if (e.name == "collision_checks_eager") s.checks_eager = e.value;
  if (e.name == "collision_checks_lazy") s.checks_lazy = e.value;
  if (e.name == "collision_checks") s.checks_total = e.value;
  if (auto it = f.counters.find(e.name); it != f.counters.end()) {
    it->second = e.value;
  } else {
    f.counters.emplace(std::string(e.name), e.value);
  }
  sql::Statement& st = insert_counter;
  st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration).bindStatic(5, e.name).bind(6, e.value);
  st.runKeepingBindings();
}

void ResultsDb::Impl::flushEventRowsLocked() {
  if (pending_rows == kRowsPerInsert) {
    for (int r = 0; r < kRowsPerInsert; ++r) bindEventRow(insert_events, 1 + r * kEventColumns, event_rows[static_cast<std::size_t>(r)]);
    insert_events.runKeepingBindings();
  } else {
    for (int r = 0; r < pending_rows; ++r) {
      bindEventRow(insert_event, 1, event_rows[static_cast<std::size_t>(r)]);
      insert_event.runKeepingBindings();
    }
  }
  pending_rows = 0;
}

void ResultsDb::Impl::writeProgressLocked(std::int64_t run_id, RunState& s, double t, int iteration) {
  s.last_progress_t = t;
  sql::Statement& st = insert_progress;
  st.bind(1, run_id).bind(2, t).bind(3, iteration);
  const RepresentationSizes& sizes = s.figures.sizes;
  for (int l = 0; l < kLayerCount; ++l) st.bind(4 + 2 * l, sizes.vertices[l]).bind(5 + 2 * l, sizes.hyperarcs[l]);
  st.bind(12, s.roadmap_vertices).bind(13, s.roadmap_edges).bind(14, s.figures.active_constraints);
  st.bind(15, s.checks_total >= 0 ? s.checks_total : s.checks_eager + s.checks_lazy);
  if (s.work_phase >= 0) {
    st.bindStatic(16, toString(static_cast<Phase>(s.work_phase))).bind(17, s.work_done).bind(18, s.work_total);
    st.bind(19, s.work_rate).bindOrNull(20, s.work_current);
  } else {
    for (int i = 16; i <= 20; ++i) st.bindNull(i);
  }
  st.run();
}

}  // namespace dash::log
