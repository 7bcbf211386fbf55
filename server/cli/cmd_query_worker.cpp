// dashbench query-worker (internal): one query of the server's SQL console, in its own process with
// CPU and memory limits (server/http/query_process.h). Started by `dashbench serve`, never by people.
#include <string>
#include <vector>

#include "server/cli/command.h"
#include "server/http/query_process.h"

namespace dash::cli {

extern const char* const kQueryWorkerHelp;
const char* const kQueryWorkerHelp =
    "usage: dashbench query-worker\n"
    "Internal: runs one read-only query of the server's query console. Reads the database path, the SQL\n"
    "and the limits as JSON on stdin and writes the rows (or the refusal) as JSON on stdout.\n";

int runQueryWorker(const std::vector<std::string>& words) {
  if (!words.empty()) return kExitBadInput;
  return http::queryWorkerMain(0, 1);
}

}  // namespace dash::cli
