#pragma once
// Typed planner events: what the planners emit, what the SQLite recorder, the tests and the live
// stream consume. Every event carries a monotonic timestamp (seconds since the run started) and the
// planning iteration; EventEmitter (event_emitter.h) stamps both.
//
// One Event = a common header plus a std::variant payload: one virtual call per event, no
// allocation beyond the payload's own strings and id vectors (short labels and type names fit in
// std::string's small-string buffer).
#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace dash::log {

/// The four representations of the paper: task space hypergraph H_T, task-extended H_TE, motion
/// hypergraph H_M and motion-extended H_ME.
enum class Layer : std::uint8_t { Task, TaskExtended, Motion, MotionExtended };
inline constexpr int kLayerCount = 4;

enum class ElementKind : std::uint8_t { Vertex, Hyperarc };

/// Added is the normal case; Removed exists for representations that drop elements (an invalid
/// roadmap-backed hyperarc, a rebuilt task space), so that event counts keep matching sizes.
enum class ElementChange : std::uint8_t { Added, Removed };

enum class ConstraintKind : std::uint8_t { Frontier, History, Motion, Interaction };
inline constexpr int kConstraintKindCount = 4;

enum class ConstraintAction : std::uint8_t { Created, Lifted };

enum class Phase : std::uint8_t {
  TaskConstruction,
  TaskQuery,
  TaskConflictDetection,
  MotionConstruction,
  MotionQuery,
  ConflictResolution,
  Validation,  ///< the plan validator run on a candidate plan inside the planning loop
  Other,
};
inline constexpr int kPhaseCount = 8;

enum class PhaseBoundary : std::uint8_t { Start, End };

/// A vertex or hyperarc added to (or removed from) one of the four representations.
struct RepresentationEvent {
  Layer layer = Layer::Task;
  ElementKind kind = ElementKind::Vertex;
  ElementChange change = ElementChange::Added;
  std::string arc_type;  ///< hyperarcs: "pick", "place", "handover", "inspect", "source", "sink",
                         ///< "composition", "transition", "move", ...; empty for vertices
  std::uint32_t id = 0;
  std::vector<std::uint32_t> head;  ///< hyperarcs only
  std::vector<std::uint32_t> tail;  ///< hyperarcs only
  std::string label;                ///< short, for people: "R1+O3"
};

struct ConstraintEvent {
  ConstraintKind kind = ConstraintKind::Frontier;
  ConstraintAction action = ConstraintAction::Created;
  std::uint32_t id = 0;  ///< lets a "lifted" event name the constraint it lifts
  std::string content;   ///< short text or JSON: "(v_pre=12, v_post=40)"
  std::vector<std::uint32_t> vertices;
  std::string conflict;  ///< the conflict that caused it, as text
};

/// Lazy-DaSH's task space expansion: an extra stable pose ("move-out" state) for an object.
struct TaskSpaceExpansionEvent {
  std::uint32_t object_id = 0;
  std::string object_label;
  std::string added;   ///< what was added, e.g. the new stable pose
  std::string reason;  ///< e.g. the contradicting constraints
};

struct PhaseEvent {
  Phase phase = Phase::Other;
  PhaseBoundary boundary = PhaseBoundary::Start;
  double duration = 0.0;  ///< End events: seconds since the matching Start
};

/// A running total (not an increment): the latest value of a counter wins.
/// Names in use: "collision_checks_eager", "collision_checks_lazy", "roadmap_vertices",
/// "roadmap_edges"; any other name is stored as well.
struct CounterEvent {
  std::string name;
  std::int64_t value = 0;
};

/// How far a long phase has got, for people watching a run: `done` of `total` units of work, what
/// is being worked on now, and the rate. Conflict resolution: task steps scheduled of the task plan's
/// steps (those taken from the last schedule count as done), the robots of the step being scheduled
/// ("ur5e_0, ur5e_3"), steps per second of this build. A producer emits one when its work starts,
/// then at most every so often of wall time, and one when it ends, with `current` empty. Progress
/// events report; nothing the planner computes depends on them (or on when they are emitted).
struct ProgressEvent {
  Phase phase = Phase::ConflictResolution;
  std::int64_t done = 0;
  std::int64_t total = 0;
  double rate = 0.0;    ///< units per second since the work started
  std::string current;  ///< what is worked on now, for people; empty: the work ended
};

using EventPayload = std::variant<RepresentationEvent, ConstraintEvent, TaskSpaceExpansionEvent,
                                  PhaseEvent, CounterEvent, ProgressEvent>;

struct Event {
  double t = 0.0;     ///< seconds since the run started (monotonic clock)
  int iteration = 0;  ///< the planner's iteration number
  EventPayload payload;
};

/// Where events go. Injected into planners (never global). An implementation states whether it
/// may be called from several threads; every sink in engine/log may be.
class EventSink {
 public:
  virtual ~EventSink() = default;
  virtual void onEvent(const Event& event) = 0;
};

/// Drops everything.
class NullSink final : public EventSink {
 public:
  void onEvent(const Event&) override {}
};

/// Forwards each event to several sinks (e.g. the SQLite recorder and the live stream).
class TeeSink final : public EventSink {
 public:
  explicit TeeSink(std::vector<EventSink*> sinks) : sinks_(std::move(sinks)) {}
  void onEvent(const Event& event) override {
    for (EventSink* s : sinks_) s->onEvent(event);
  }

 private:
  std::vector<EventSink*> sinks_;
};

// Names as they appear in the database, the JSON stream and the CLI ("task_extended", "hyperarc").
inline constexpr std::array<const char*, kLayerCount> kLayerNames = {"task", "task_extended", "motion",
                                                                     "motion_extended"};
inline constexpr std::array<const char*, kPhaseCount> kPhaseNames = {
    "task_construction", "task_query",      "task_conflict_detection", "motion_construction",
    "motion_query",      "conflict_resolution", "validation",           "other"};
inline constexpr std::array<const char*, kConstraintKindCount> kConstraintKindNames = {
    "frontier", "history", "motion", "interaction"};

inline const char* toString(Layer v) { return kLayerNames[static_cast<int>(v)]; }
inline const char* toString(Phase v) { return kPhaseNames[static_cast<int>(v)]; }
inline const char* toString(ConstraintKind v) { return kConstraintKindNames[static_cast<int>(v)]; }
inline const char* toString(ElementKind v) { return v == ElementKind::Vertex ? "vertex" : "hyperarc"; }
inline const char* toString(ElementChange v) { return v == ElementChange::Added ? "added" : "removed"; }
inline const char* toString(ConstraintAction v) { return v == ConstraintAction::Created ? "created" : "lifted"; }
inline const char* toString(PhaseBoundary v) { return v == PhaseBoundary::Start ? "start" : "end"; }

/// The payload's type name: "representation", "constraint", "task_space_expansion", "phase", "counter",
/// "progress".
inline const char* typeName(const EventPayload& p) {
  static constexpr std::array<const char*, 6> kNames = {"representation", "constraint", "task_space_expansion",
                                                        "phase", "counter", "progress"};
  return kNames[p.index()];
}

}  // namespace dash::log
