// The writer thread of a ResultsDb: drains recorders' batches into SQLite, one transaction per
// drain, and keeps each run's running sizes for the progress snapshots.
#include <charconv>
#include <cstdio>

#include "engine/log/results_db_impl.h"

namespace dash::log {
namespace {

// "[1,2,3]": JSON, so SQL can read it with json_each.
void writeIds(const std::vector<std::uint32_t>& ids, std::string& out) {
  out.clear();
  out.push_back('[');
  char buffer[16];
  for (std::size_t i = 0; i < ids.size(); ++i) {
    if (i != 0) out.push_back(',');
    const auto end = std::to_chars(buffer, buffer + sizeof(buffer), ids[i]).ptr;
    out.append(buffer, end);
  }
  out.push_back(']');
}

}  // namespace

void ResultsDb::Impl::enqueue(Batch batch) {
  if (batch.events.empty()) return;
  std::unique_lock lock(queue_mutex);
  if (stopping) return;  // the database is closing; its recorders were closed first
  if (!writer.joinable()) writer = std::thread([this] { writerLoop(); });
  queue_changed.wait(lock, [&] { return queued_events < options.max_queued_events || stopping; });
  queued_events += batch.events.size();
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
        for (const Batch& batch : work) {
          RunState& state = run_states[batch.run_id];
          if (!state.error.empty()) continue;
          for (const Event& e : batch.events) writeEventLocked(batch.run_id, state, e);
        }
        commitLocked();
      } catch (const std::exception& e) {
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

void ResultsDb::Impl::writeEventLocked(std::int64_t run_id, RunState& s, const Event& e) {
  const std::int64_t seq = s.seq++;
  if (const auto* r = std::get_if<RepresentationEvent>(&e.payload)) {
    const int layer = static_cast<int>(r->layer);
    auto& count = r->kind == ElementKind::Vertex ? s.sizes.vertices[layer] : s.sizes.hyperarcs[layer];
    count += r->change == ElementChange::Added ? 1 : -1;
    sql::Statement& st = insert_event;
    st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration);
    st.bindStatic(5, toString(r->layer)).bindStatic(6, toString(r->kind)).bindStatic(7, toString(r->change));
    if (r->kind == ElementKind::Hyperarc) {
      writeIds(r->head, s.head_buffer);
      writeIds(r->tail, s.tail_buffer);
      st.bindStatic(8, r->arc_type).bindStatic(10, s.head_buffer).bindStatic(11, s.tail_buffer);
    } else {
      st.bindNull(8).bindNull(10).bindNull(11);
    }
    st.bind(9, static_cast<std::int64_t>(r->id));
    if (r->label.empty()) {
      st.bindNull(12);
    } else {
      st.bindStatic(12, r->label);
    }
    st.run();
  } else if (const auto* c = std::get_if<ConstraintEvent>(&e.payload)) {
    s.active_constraints += c->action == ConstraintAction::Created ? 1 : -1;
    writeIds(c->vertices, s.head_buffer);
    sql::Statement& st = insert_constraint;
    st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration);
    st.bindStatic(5, toString(c->kind)).bindStatic(6, toString(c->action)).bind(7, static_cast<std::int64_t>(c->id));
    st.bindStatic(8, c->content).bindStatic(9, s.head_buffer).bindOrNull(10, c->conflict);
    st.run();
  } else if (const auto* x = std::get_if<TaskSpaceExpansionEvent>(&e.payload)) {
    sql::Statement& st = insert_expansion;
    st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration).bind(5, static_cast<std::int64_t>(x->object_id));
    st.bindStatic(6, x->object_label).bindStatic(7, x->added).bindStatic(8, x->reason);
    st.run();
  } else if (const auto* p = std::get_if<PhaseEvent>(&e.payload)) {
    sql::Statement& st = insert_phase;
    st.bind(1, run_id).bind(2, seq).bind(3, e.iteration).bindStatic(4, toString(p->phase));
    st.bind(5, e.t - p->duration).bind(6, e.t).bind(7, p->duration);
    st.run();
    if (e.t - s.last_progress_t >= s.progress_interval) writeProgressLocked(run_id, s, e.t, e.iteration);
  } else if (const auto* k = std::get_if<CounterEvent>(&e.payload)) {
    if (k->name == "roadmap_vertices") s.roadmap_vertices = k->value;
    if (k->name == "roadmap_edges") s.roadmap_edges = k->value;
    if (k->name == "collision_checks_eager") s.checks_eager = k->value;
    if (k->name == "collision_checks_lazy") s.checks_lazy = k->value;
    if (k->name == "collision_checks") s.checks_total = k->value;
    sql::Statement& st = insert_counter;
    st.bind(1, run_id).bind(2, seq).bind(3, e.t).bind(4, e.iteration).bindStatic(5, k->name).bind(6, k->value);
    st.run();
  }
}

void ResultsDb::Impl::writeProgressLocked(std::int64_t run_id, RunState& s, double t, int iteration) {
  s.last_progress_t = t;
  sql::Statement& st = insert_progress;
  st.bind(1, run_id).bind(2, t).bind(3, iteration);
  for (int l = 0; l < kLayerCount; ++l) st.bind(4 + 2 * l, s.sizes.vertices[l]).bind(5 + 2 * l, s.sizes.hyperarcs[l]);
  st.bind(12, s.roadmap_vertices).bind(13, s.roadmap_edges).bind(14, s.active_constraints);
  st.bind(15, s.checks_total >= 0 ? s.checks_total : s.checks_eager + s.checks_lazy);
  st.run();
}

}  // namespace dash::log
