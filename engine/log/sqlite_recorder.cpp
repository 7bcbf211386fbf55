#include "engine/log/sqlite_recorder.h"

#include <charconv>
#include <exception>

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

SqliteRecorder::SqliteRecorder(ResultsDb::Impl& db, std::string uuid, std::int64_t run_id, RecorderOptions options)
    : db_(&db), uuid_(std::move(uuid)), run_id_(run_id), options_(options) {}

SqliteRecorder::~SqliteRecorder() {
  if (db_ == nullptr) return;
  std::lock_guard lock(db_->mutex);
  if (auto it = db_->active.find(uuid_); it != db_->active.end() && it->second.recorder == this) {
    it->second.recorder = nullptr;
  }
}

std::int64_t SqliteRecorder::storedEvents() const {
  if (db_ == nullptr) return seq_;
  std::lock_guard lock(db_->mutex);
  return seq_;
}

std::string SqliteRecorder::error() const {
  if (db_ == nullptr) return error_;
  std::lock_guard lock(db_->mutex);
  return error_;
}

void SqliteRecorder::onEvent(const Event& event) {
  if (db_ == nullptr) return;
  std::lock_guard lock(db_->mutex);
  if (finished_ || !error_.empty()) return;
  try {
    const auto* phase = std::get_if<PhaseEvent>(&event.payload);
    if (phase != nullptr && phase->boundary == PhaseBoundary::Start) return;  // stored once, at its end
    db_->beginWriteLocked();
    std::visit(
        [&](const auto& p) {
          using T = std::decay_t<decltype(p)>;
          if constexpr (std::is_same_v<T, RepresentationEvent>) writeRepresentation(event, p);
          if constexpr (std::is_same_v<T, ConstraintEvent>) writeConstraint(event, p);
          if constexpr (std::is_same_v<T, TaskSpaceExpansionEvent>) writeExpansion(event, p);
          if constexpr (std::is_same_v<T, PhaseEvent>) writePhase(event, p);
          if constexpr (std::is_same_v<T, CounterEvent>) writeCounter(event, p);
        },
        event.payload);
    ++seq_;
    if (phase != nullptr && event.t - last_progress_t_ >= options_.progress_interval) {
      writeProgress(event.t, event.iteration);
    }
    db_->afterWriteLocked();
  } catch (const std::exception& e) {
    error_ = e.what();
    db_->rollbackLocked();
  }
}

void SqliteRecorder::writeRepresentation(const Event& e, const RepresentationEvent& r) {
  const int layer = static_cast<int>(r.layer);
  auto& count = r.kind == ElementKind::Vertex ? sizes_.vertices[layer] : sizes_.hyperarcs[layer];
  count += r.change == ElementChange::Added ? 1 : -1;

  sql::Statement& st = db_->insert_event;
  st.bind(1, run_id_).bind(2, seq_).bind(3, e.t).bind(4, e.iteration);
  st.bindStatic(5, toString(r.layer)).bindStatic(6, toString(r.kind)).bindStatic(7, toString(r.change));
  if (r.kind == ElementKind::Hyperarc) {
    writeIds(r.head, head_buffer_);
    writeIds(r.tail, tail_buffer_);
    st.bindStatic(8, r.arc_type).bindStatic(10, head_buffer_).bindStatic(11, tail_buffer_);
  } else {
    st.bindNull(8).bindNull(10).bindNull(11);
  }
  st.bind(9, static_cast<std::int64_t>(r.id));
  if (r.label.empty()) {
    st.bindNull(12);
  } else {
    st.bindStatic(12, r.label);
  }
  st.run();
}

void SqliteRecorder::writeConstraint(const Event& e, const ConstraintEvent& c) {
  active_constraints_ += c.action == ConstraintAction::Created ? 1 : -1;
  writeIds(c.vertices, head_buffer_);
  sql::Statement& st = db_->insert_constraint;
  st.bind(1, run_id_).bind(2, seq_).bind(3, e.t).bind(4, e.iteration);
  st.bindStatic(5, toString(c.kind)).bindStatic(6, toString(c.action)).bind(7, static_cast<std::int64_t>(c.id));
  st.bindStatic(8, c.content).bindStatic(9, head_buffer_).bindStatic(10, c.conflict);
  st.run();
}

void SqliteRecorder::writeExpansion(const Event& e, const TaskSpaceExpansionEvent& x) {
  sql::Statement& st = db_->insert_expansion;
  st.bind(1, run_id_).bind(2, seq_).bind(3, e.t).bind(4, e.iteration).bind(5, static_cast<std::int64_t>(x.object_id));
  st.bindStatic(6, x.object_label).bindStatic(7, x.added).bindStatic(8, x.reason);
  st.run();
}

void SqliteRecorder::writePhase(const Event& e, const PhaseEvent& p) {
  sql::Statement& st = db_->insert_phase;
  st.bind(1, run_id_).bind(2, seq_).bind(3, e.iteration).bindStatic(4, toString(p.phase));
  st.bind(5, e.t - p.duration).bind(6, e.t).bind(7, p.duration);
  st.run();
}

void SqliteRecorder::writeCounter(const Event& e, const CounterEvent& c) {
  if (c.name == "roadmap_vertices") roadmap_vertices_ = c.value;
  if (c.name == "roadmap_edges") roadmap_edges_ = c.value;
  if (c.name == "collision_checks_eager") checks_eager_ = c.value;
  if (c.name == "collision_checks_lazy") checks_lazy_ = c.value;
  if (c.name == "collision_checks") checks_total_ = c.value;
  sql::Statement& st = db_->insert_counter;
  st.bind(1, run_id_).bind(2, seq_).bind(3, e.t).bind(4, e.iteration).bindStatic(5, c.name).bind(6, c.value);
  st.run();
}

void SqliteRecorder::writeProgress(double t, int iteration) {
  last_progress_t_ = t;
  sql::Statement& st = db_->insert_progress;
  st.bind(1, run_id_).bind(2, t).bind(3, iteration);
  for (int l = 0; l < kLayerCount; ++l) {
    st.bind(4 + 2 * l, sizes_.vertices[l]).bind(5 + 2 * l, sizes_.hyperarcs[l]);
  }
  st.bind(12, roadmap_vertices_).bind(13, roadmap_edges_).bind(14, active_constraints_);
  st.bind(15, checks_total_ >= 0 ? checks_total_ : checks_eager_ + checks_lazy_);
  st.run();
}

}  // namespace dash::log
