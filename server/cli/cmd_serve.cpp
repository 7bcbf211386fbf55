#include <cstdio>

#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kServeHelp;
const char* const kServeHelp =
    "usage: dashbench serve [--host 127.0.0.1] [--port 8080] [--db data/results.db] [--token-file FILE]\n"
    "Serve the web dashboard and the JSON API.\n";

int runServe(const std::vector<std::string>& words) {
  Args args(words, {.options = {"host", "port", "db", "token-file"}, .flags = {}});
  std::fprintf(stderr,
               "dashbench serve: the HTTP server and dashboard are not part of this build yet "
               "(issue: Embedded HTTP server and web dashboard). Nothing is being served.\n");
  return kExitProblems;
}

}  // namespace dash::cli
