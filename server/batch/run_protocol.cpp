#include "server/batch/run_protocol.h"

#include <bit>
#include <cstring>
#include <type_traits>
#include <variant>
#include <vector>

namespace dash::batch::proto {
namespace {

// Little-endian fixed-width encoding (every target we build for is little endian; the static
// assert keeps it honest).
static_assert(std::endian::native == std::endian::little, "the run protocol assumes a little-endian host");

class Writer {
 public:
  /// Starts a frame of `type` at the end of `out`; the length is patched by the destructor.
  Writer(std::string& out, MessageType type) : out_(out), start_(out.size()) {
    out_.push_back(static_cast<char>(type));
    out_.append(4, '\0');
  }
  ~Writer() {
    const auto length = static_cast<std::uint32_t>(out_.size() - start_ - 5);
    std::memcpy(out_.data() + start_ + 1, &length, 4);
  }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  template <class T>
  Writer& raw(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out_.append(bytes, sizeof(T));
    return *this;
  }
  Writer& u8(std::uint8_t v) { return raw(v); }
  Writer& u32(std::uint32_t v) { return raw(v); }
  Writer& i32(std::int32_t v) { return raw(v); }
  Writer& i64(std::int64_t v) { return raw(v); }
  Writer& f64(double v) { return raw(v); }
  Writer& str(const std::string& s) {
    u32(static_cast<std::uint32_t>(s.size()));
    out_.append(s);
    return *this;
  }
  Writer& ids(const std::vector<std::uint32_t>& v) {
    u32(static_cast<std::uint32_t>(v.size()));
    if (!v.empty()) out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(std::uint32_t));
    return *this;
  }

 private:
  std::string& out_;
  std::size_t start_;
};

class Reader {
 public:
  explicit Reader(const std::string& payload) : data_(payload) {}

  template <class T>
  T raw() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, data_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  std::uint8_t u8() { return raw<std::uint8_t>(); }
  std::uint32_t u32() { return raw<std::uint32_t>(); }
  std::int32_t i32() { return raw<std::int32_t>(); }
  std::int64_t i64() { return raw<std::int64_t>(); }
  double f64() { return raw<double>(); }
  std::string str() {
    const std::uint32_t n = u32();
    need(n);
    std::string s = data_.substr(pos_, n);
    pos_ += n;
    return s;
  }
  std::vector<std::uint32_t> ids() {
    const std::uint32_t n = u32();
    need(static_cast<std::size_t>(n) * sizeof(std::uint32_t));
    std::vector<std::uint32_t> v(n);
    if (n > 0) std::memcpy(v.data(), data_.data() + pos_, n * sizeof(std::uint32_t));
    pos_ += n * sizeof(std::uint32_t);
    return v;
  }
  template <class E>
  E enumeration(int count) {
    const std::uint8_t v = u8();
    if (v >= count) throw ProtocolError("enum value " + std::to_string(v) + " out of range");
    return static_cast<E>(v);
  }
  void end() const {
    if (pos_ != data_.size()) throw ProtocolError("trailing bytes in a frame");
  }

 private:
  void need(std::size_t n) const {
    if (data_.size() - pos_ < n) throw ProtocolError("truncated frame");
  }
  const std::string& data_;
  std::size_t pos_ = 0;
};

bool knownType(char c) {
  switch (static_cast<MessageType>(c)) {
    case MessageType::kHello:
    case MessageType::kStarted:
    case MessageType::kEvent:
    case MessageType::kResult:
    case MessageType::kError:
      return true;
  }
  return false;
}

}  // namespace

void appendHello(std::string& out, std::int64_t pid) {
  Writer(out, MessageType::kHello).u32(kProtocolVersion).i64(pid);
}

void appendStarted(std::string& out, const std::string& scene_name) {
  Writer(out, MessageType::kStarted).str(scene_name);
}

void appendEvent(std::string& out, const log::Event& event) {
  Writer w(out, MessageType::kEvent);
  w.f64(event.t).i32(event.iteration).u8(static_cast<std::uint8_t>(event.payload.index()));
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, log::RepresentationEvent>) {
          w.u8(static_cast<std::uint8_t>(p.layer)).u8(static_cast<std::uint8_t>(p.kind));
          w.u8(static_cast<std::uint8_t>(p.change)).str(p.arc_type).u32(p.id).ids(p.head).ids(p.tail).str(p.label);
        } else if constexpr (std::is_same_v<T, log::ConstraintEvent>) {
          w.u8(static_cast<std::uint8_t>(p.kind)).u8(static_cast<std::uint8_t>(p.action)).u32(p.id);
          w.str(p.content).ids(p.vertices).str(p.conflict);
        } else if constexpr (std::is_same_v<T, log::TaskSpaceExpansionEvent>) {
          w.u32(p.object_id).str(p.object_label).str(p.added).str(p.reason);
        } else if constexpr (std::is_same_v<T, log::PhaseEvent>) {
          w.u8(static_cast<std::uint8_t>(p.phase)).u8(static_cast<std::uint8_t>(p.boundary)).f64(p.duration);
        } else if constexpr (std::is_same_v<T, log::ProgressEvent>) {
          w.u8(static_cast<std::uint8_t>(p.phase)).i64(p.done).i64(p.total).f64(p.rate).str(p.current);
        } else {
          static_assert(std::is_same_v<T, log::CounterEvent>);
          w.str(p.name).i64(p.value);
        }
      },
      event.payload);
}

void appendResult(std::string& out, const ChildResult& r) {
  Writer w(out, MessageType::kResult);
  w.u8(static_cast<std::uint8_t>(r.outcome)).str(r.message).str(r.plan_json).str(r.task_plan_json);
  const PlanStats& s = r.stats;
  for (double d : s.phase_seconds) w.f64(d);
  const RepresentationCounts& z = s.sizes;
  for (std::size_t v :
       {z.task_vertices, z.task_hyperarcs, z.task_extended_vertices, z.task_extended_hyperarcs, z.motion_vertices,
        z.motion_hyperarcs, z.motion_extended_vertices, z.motion_extended_hyperarcs}) {
    w.i64(static_cast<std::int64_t>(v));
  }
  w.i64(s.iterations).i64(s.collision_checks_eager).i64(s.collision_checks_lazy).i64(s.roadmap_vertices);
  w.i64(s.roadmap_edges).i64(s.task_constraints).i64(s.motion_constraints).i64(s.task_space_expansions);
  w.f64(s.makespan).f64(s.path_length).f64(s.wall_seconds).f64(r.solve_seconds).f64(r.peak_memory_mb);
}

void appendError(std::string& out, const ChildError& e) { Writer(out, MessageType::kError).str(e.kind).str(e.message); }

void FrameDecoder::feed(const char* data, std::size_t size) {
  if (offset_ > 0 && offset_ == buffer_.size()) {
    buffer_.clear();
    offset_ = 0;
  } else if (offset_ > (1u << 20)) {
    buffer_.erase(0, offset_);
    offset_ = 0;
  }
  buffer_.append(data, size);
}

bool FrameDecoder::next(Frame& frame) {
  if (buffer_.size() - offset_ < 5) return false;
  const char type = buffer_[offset_];
  if (!knownType(type)) throw ProtocolError("unknown frame type " + std::to_string(static_cast<int>(type)));
  std::uint32_t length = 0;
  std::memcpy(&length, buffer_.data() + offset_ + 1, 4);
  if (length > kMaxFrameBytes) throw ProtocolError("frame of " + std::to_string(length) + " bytes is too large");
  if (buffer_.size() - offset_ - 5 < length) return false;
  frame.type = static_cast<MessageType>(type);
  frame.payload.assign(buffer_, offset_ + 5, length);
  offset_ += 5 + length;
  return true;
}

Hello decodeHello(const std::string& payload) {
  Reader r(payload);
  Hello h;
  h.version = r.u32();
  h.pid = r.i64();
  r.end();
  return h;
}

std::string decodeStarted(const std::string& payload) {
  Reader r(payload);
  std::string name = r.str();
  r.end();
  return name;
}

log::Event decodeEvent(const std::string& payload) {
  Reader r(payload);
  log::Event e;
  e.t = r.f64();
  e.iteration = r.i32();
  const std::uint8_t index = r.u8();
  switch (index) {
    case 0: {
      log::RepresentationEvent p;
      p.layer = r.enumeration<log::Layer>(log::kLayerCount);
      p.kind = r.enumeration<log::ElementKind>(2);
      p.change = r.enumeration<log::ElementChange>(2);
      p.arc_type = r.str();
      p.id = r.u32();
      p.head = r.ids();
      p.tail = r.ids();
      p.label = r.str();
      e.payload = std::move(p);
      break;
    }
    case 1: {
      log::ConstraintEvent p;
      p.kind = r.enumeration<log::ConstraintKind>(log::kConstraintKindCount);
      p.action = r.enumeration<log::ConstraintAction>(2);
      p.id = r.u32();
      p.content = r.str();
      p.vertices = r.ids();
      p.conflict = r.str();
      e.payload = std::move(p);
      break;
    }
    case 2: {
      log::TaskSpaceExpansionEvent p;
      p.object_id = r.u32();
      p.object_label = r.str();
      p.added = r.str();
      p.reason = r.str();
      e.payload = std::move(p);
      break;
    }
    case 3: {
      log::PhaseEvent p;
      p.phase = r.enumeration<log::Phase>(log::kPhaseCount);
      p.boundary = r.enumeration<log::PhaseBoundary>(2);
      p.duration = r.f64();
      e.payload = p;
      break;
    }
    case 4: {
      log::CounterEvent p;
      p.name = r.str();
      p.value = r.i64();
      e.payload = std::move(p);
      break;
    }
    case 5: {
      log::ProgressEvent p;
      p.phase = r.enumeration<log::Phase>(log::kPhaseCount);
      p.done = r.i64();
      p.total = r.i64();
      p.rate = r.f64();
      p.current = r.str();
      e.payload = std::move(p);
      break;
    }
    default:
      throw ProtocolError("unknown event payload " + std::to_string(index));
  }
  r.end();
  return e;
}

ChildResult decodeResult(const std::string& payload) {
  Reader r(payload);
  ChildResult out;
  out.outcome = r.enumeration<PlanOutcome>(4);
  out.message = r.str();
  out.plan_json = r.str();
  out.task_plan_json = r.str();
  PlanStats& s = out.stats;
  for (double& d : s.phase_seconds) d = r.f64();
  RepresentationCounts& z = s.sizes;
  for (std::size_t* v :
       {&z.task_vertices, &z.task_hyperarcs, &z.task_extended_vertices, &z.task_extended_hyperarcs, &z.motion_vertices,
        &z.motion_hyperarcs, &z.motion_extended_vertices, &z.motion_extended_hyperarcs}) {
    *v = static_cast<std::size_t>(r.i64());
  }
  s.iterations = static_cast<int>(r.i64());
  s.collision_checks_eager = r.i64();
  s.collision_checks_lazy = r.i64();
  s.roadmap_vertices = r.i64();
  s.roadmap_edges = r.i64();
  s.task_constraints = r.i64();
  s.motion_constraints = r.i64();
  s.task_space_expansions = r.i64();
  s.makespan = r.f64();
  s.path_length = r.f64();
  s.wall_seconds = r.f64();
  out.solve_seconds = r.f64();
  out.peak_memory_mb = r.f64();
  r.end();
  return out;
}

ChildError decodeError(const std::string& payload) {
  Reader r(payload);
  ChildError e;
  e.kind = r.str();
  e.message = r.str();
  r.end();
  return e;
}

}  // namespace dash::batch::proto
