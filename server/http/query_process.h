#pragma once
// The query console's queries run in a child process (issue 24): `dashbench query-worker` (a hidden
// subcommand) reads one request as JSON on stdin, runs log::runReadOnlyQuery with every guard of
// db_query.h (authorizer, cell length limit, progress-handler time limit, byte budget) and writes
// the answer as JSON on stdout. The parent gives it limits no SQLite guard can give:
// - RLIMIT_CPU (the time limit, rounded up) and a wall-clock kill at the time limit + 0.25 s: one
//   expensive function call (trim/instr/replace of long strings, a backtracking LIKE or GLOB)
//   runs inside one VM step, where the progress handler never gets a say;
// - RLIMIT_AS (1 GiB) and a SQLite heap limit in the child: the memory one query may take;
// - a kill when the client goes away (the caller's `cancelled`), and a cap on the answer's size: the
//   child writes the API's answer itself, its rows bounded in JSON bytes, and the server passes it on.
// The server's own heap and threads never see a console query.
#include <cstddef>
#include <functional>
#include <string>

#include "engine/log/db_query.h"

namespace dash::http {

struct QueryProcessLimits {
  std::size_t address_space_bytes = std::size_t{1} << 30;  ///< RLIMIT_AS of the child
  std::int64_t sqlite_heap_bytes = std::int64_t{384} << 20;  ///< sqlite3_hard_heap_limit64 in the child
  /// The answer may pass the rows' byte budget (QueryLimits::max_result_bytes) by this much (the
  /// column names, the closing keys); more on stdout: killed, refused.
  std::size_t max_answer_overhead_bytes = std::size_t{2} << 20;
  double kill_grace_seconds = 0.25;                          ///< after the query's time limit
};

/// Runs `sql` on `db_path` in `executable query-worker` (empty: /proc/self/exe) and returns the
/// answer's JSON text as the API sends it: {"columns", "rows", "truncated", "max_rows", "max_bytes"},
/// its rows at most limits.max_result_bytes of JSON. The child writes it; this process only passes
/// the bytes on (no JSON tree of the rows is built here: four clients once took the server from 191
/// to 877 MB). Throws what runReadOnlyQuery throws (QueryRefused, InputError), QueryRefused(TimeLimit)
/// when the child was killed for time, InputError when it ran out of memory, and std::runtime_error
/// when it could not run. `cancelled` is asked about every 100 ms; true kills the child (InputError).
std::string runQueryInChild(const std::string& executable, const std::string& db_path, const std::string& sql,
                            const log::QueryLimits& limits, const std::function<bool()>& cancelled = {},
                            const QueryProcessLimits& process = {});

/// The child's side (`dashbench query-worker`): one request from `in_fd`, its answer to `out_fd`.
/// Returns the exit status (0 when an answer, even a refusal, was written).
int queryWorkerMain(int in_fd, int out_fd);

}  // namespace dash::http
