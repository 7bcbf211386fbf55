// dashbench run-one (internal): one run of a batch, in its own process. Started by the batch
// runner (server/batch/batch_runner.h), never by people: it streams its events and result to the
// descriptor --fd in the runner's binary protocol.
#include <string>

#include "server/batch/batch_spec.h"
#include "server/batch/run_one.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kRunOneHelp;
const char* const kRunOneHelp =
    "usage: dashbench run-one --fd N --run JSON\n"
    "Internal: one run of a batch, started by `dashbench batch run` in a process of its own. Plans the\n"
    "run described by JSON and writes its events and result to descriptor N (binary frames).\n";

int runRunOne(const std::vector<std::string>& words) {
  Args args(words, {.options = {"fd", "run"}, .flags = {}});
  const long long fd = args.integer("fd", -1);
  DASH_THROW_UNLESS(fd >= 0, "run-one needs --fd N");
  return batch::runOneChild(batch::RunSpec::fromJson(args.require("run")), static_cast<int>(fd));
}

}  // namespace dash::cli
