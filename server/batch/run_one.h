#pragma once
// The child side of a batch run: `dashbench run-one --fd N --run JSON` (hidden subcommand).
// Generates the run's scene, plans it with the run's planner and settings, and streams hello,
// started, every event and the result (or an error) to file descriptor N (run_protocol.h).
// SIGTERM and SIGINT set the planner's stop flag: the planner returns (cancelled) and the child
// still reports its result. It never touches the database.
#include "server/batch/batch_spec.h"

namespace dash::batch {

// Exit codes of the child (besides 0, a result was sent).
inline constexpr int kChildExitInput = 2;        ///< bad run description or scene generation failed
inline constexpr int kChildExitOutOfMemory = 4;  ///< std::bad_alloc (the memory limit)
inline constexpr int kChildExitInternal = 5;     ///< any other exception
inline constexpr int kChildExitPipe = 6;         ///< the parent's pipe failed

/// Runs `run`, writing frames to `fd`; returns the process exit code.
int runOneChild(const RunSpec& run, int fd);

}  // namespace dash::batch
