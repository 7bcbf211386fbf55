#pragma once
// The pipe protocol between a batch's runner (parent) and a run's process (`dashbench run-one`).
// Only the parent writes the database: the child streams its events and final result back as
// length-prefixed binary frames:
//
//   frame   = type (1 byte) | payload length (u32, little endian) | payload
//   H hello   : u32 protocol version, i64 pid
//   S started : scene name (the scene is generated; the planner's clock starts now)
//   E event   : f64 t, i32 iteration, u8 payload index, then the payload's fields
//   R result  : outcome, message, plan JSON, task-plan JSON, PlanStats, solve seconds, peak MB
//   X error   : kind ("input", "out-of-memory", "internal"), message
//
// Strings are u32 length + bytes; id lists are u32 count + u32 each; numbers little endian.
// A decoder that meets a malformed frame throws ProtocolError; the parent then kills the child
// and records the run as crashed.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "engine/events/events.h"
#include "engine/planners/planner.h"

namespace dash::batch::proto {

inline constexpr std::uint32_t kProtocolVersion = 3;  // 2: progress events (payload 5); 3: wall_seconds
inline constexpr std::uint32_t kMaxFrameBytes = 512u << 20;  ///< a plan JSON can be large

enum class MessageType : char { kHello = 'H', kStarted = 'S', kEvent = 'E', kResult = 'R', kError = 'X' };

class ProtocolError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What the child reports at the end of its run.
struct ChildResult {
  PlanOutcome outcome = PlanOutcome::kInfeasible;
  std::string message;
  std::string plan_json;       ///< dashbench.plan/1 when solved with a plan
  std::string task_plan_json;  ///< task-only runs: the unvalidated schedule
  PlanStats stats;
  double solve_seconds = 0.0;   ///< wall time of Planner::solve
  double peak_memory_mb = 0.0;  ///< the child's peak RSS
};

struct ChildError {
  std::string kind;  ///< "input", "out-of-memory", "internal"
  std::string message;
};

// --- encoding (each appends one whole frame to `out`) ---
void appendHello(std::string& out, std::int64_t pid);
void appendStarted(std::string& out, const std::string& scene_name);
void appendEvent(std::string& out, const log::Event& event);
void appendResult(std::string& out, const ChildResult& result);
void appendError(std::string& out, const ChildError& error);

// --- decoding ---
struct Frame {
  MessageType type = MessageType::kHello;
  std::string payload;
};

/// Splits a byte stream into frames. feed() the bytes as they arrive; next() yields whole frames.
class FrameDecoder {
 public:
  void feed(const char* data, std::size_t size);
  /// True and fills `frame` when a whole frame is buffered. Throws ProtocolError on an unknown type
  /// or an oversized length.
  bool next(Frame& frame);
  /// Bytes of an incomplete frame still buffered (non-zero at EOF means the child died mid-write).
  std::size_t pending() const { return buffer_.size() - offset_; }

 private:
  std::string buffer_;
  std::size_t offset_ = 0;
};

struct Hello {
  std::uint32_t version = 0;
  std::int64_t pid = 0;
};
Hello decodeHello(const std::string& payload);
std::string decodeStarted(const std::string& payload);
log::Event decodeEvent(const std::string& payload);
ChildResult decodeResult(const std::string& payload);
ChildError decodeError(const std::string& payload);

}  // namespace dash::batch::proto
