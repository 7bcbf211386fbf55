#pragma once
// A run's child process as the batch runner's thread sees it (batch_runner.h): its pipes, its timers
// and what it has sent so far, and the runner's ways with it: reading its pipes without blocking,
// signalling it, and waiting (poll) for any of its children or the runner's wake-up pipe.
#include <sys/types.h>

#include <chrono>
#include <functional>
#include <list>
#include <memory>
#include <optional>
#include <string>

#include "engine/core/stopwatch.h"
#include "engine/log/sqlite_recorder.h"
#include "server/batch/run_process.h"
#include "server/batch/run_protocol.h"

namespace dash::batch {

struct RunChild {
  RunSpec run;
  std::string uuid;
  pid_t pid = -1;
  int msg_fd = -1;
  int err_fd = -1;
  proto::FrameDecoder decoder;
  std::string stderr_tail;
  std::unique_ptr<log::SqliteRecorder> recorder;
  Clock::time_point spawned;
  Clock::time_point term_at;  ///< SIGTERM for the time limit
  Clock::time_point kill_at;  ///< SIGKILL after SIGTERM
  bool started = false;       ///< the planner's clock started ('S')
  bool term_sent = false;
  bool kill_sent = false;
  StopReason stop = StopReason::kNone;
  std::optional<proto::ChildResult> result;
  std::optional<proto::ChildError> error;
  std::string protocol_error;
  std::string spawn_error;
  std::optional<log::ProgressEvent> work;  ///< its planner's latest progress event
  std::optional<log::Phase> phase;         ///< the phase its planner is in (its latest phase start)
};

/// What the runner does with one complete message of a child; a proto::ProtocolError from it counts
/// as a malformed message.
using FrameHandler = std::function<void(RunChild&, const proto::Frame&)>;

/// SIGTERM (once, if the process runs), SIGKILL due `grace_seconds` later.
void stopChild(RunChild& c, StopReason why, double grace_seconds);
/// SIGKILL (once, if the process runs).
void killChild(RunChild& c);

/// Reads whatever the non-blocking pipe `fd` holds, to drop it (the runner's wake-up pipe).
void drainPipe(int fd);

/// Waits until a pipe of `children` or `wake_fd` has something, or until the next SIGTERM or SIGKILL
/// of a child is due (at most `longest`), then reads what came: stderr into the child's tail, messages
/// through `handle` (a malformed message kills the child). A pipe at its end is closed (fd -1).
/// Throws std::runtime_error if poll fails.
void waitForChildren(std::list<RunChild>& children, int wake_fd, std::chrono::milliseconds longest,
                     const FrameHandler& handle);

}  // namespace dash::batch
