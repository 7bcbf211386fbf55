// dashbench batch plan|run|resume|status: experiment batches from spec files (experiments/*.json).
// The runner is server/batch's BatchRunner, the same one the server uses.
#include <signal.h>

#include <cstdio>
#include <mutex>
#include <string>

#include "engine/log/results_db.h"
#include "server/batch/batch_runner.h"
#include "server/batch/batch_spec.h"
#include "server/batch/batch_store.h"
#include "server/batch/progress_printer.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kBatchHelp;
const char* const kBatchHelp =
    "usage: dashbench batch plan FILE [--max-runs N]\n"
    "       dashbench batch run FILE --db DB [--workers N] [--quiet] [--max-runs N] [--id ID]\n"
    "       dashbench batch resume --db DB BATCH_ID [--workers N] [--quiet] [--force]\n"
    "       dashbench batch status --db DB [BATCH_ID]\n"
    "Experiment batches: a spec file (see experiments/README.md) is a grid of scenario families and\n"
    "parameters x planner configurations x seeds, with a time and memory limit per run.\n"
    "  plan     validate FILE and print the expanded runs without running them\n"
    "  run      run every run of FILE, each in its own process, into the results database DB\n"
    "           (created if missing). The batch id is printed first; progress goes to stderr.\n"
    "  resume   run what batch BATCH_ID is missing after its runner was killed or cancelled:\n"
    "           runs never started, cancelled, or left 'running' (their partial rows are replaced)\n"
    "  status   list the batches of DB (or one) with their runs per status\n"
    "Options:\n"
    "  --workers N    runs at once (default 1)\n"
    "  --quiet        no progress on stderr (without a terminal: one line per finished run)\n"
    "  --max-runs N   refuse specs that expand to more runs (default 10000)\n"
    "  --id ID        the new batch's id (default: NAME-yyyymmdd-hhmmss-xxxx)\n"
    "  --force        resume even if the batch's runner seems alive (its heartbeat is fresh)\n"
    "Ctrl-C stops a batch cleanly: running runs get SIGTERM (then SIGKILL after 2 s) and are recorded\n"
    "as cancelled; a second Ctrl-C kills them at once. Resume it later with `batch resume`.\n"
    "Exit codes: 0 the batch finished, 2 bad input, 1 the runner failed, 130 cancelled.\n";

namespace {

batch::BatchRunner* g_runner = nullptr;
extern "C" void onInterrupt(int) {
  if (g_runner != nullptr) g_runner->cancel();
}

std::size_t maxRuns(const Args& args) {
  const long long n = args.integer("max-runs", 10000);
  DASH_THROW_UNLESS(n >= 1, "--max-runs must be at least 1");
  return static_cast<std::size_t>(n);
}

int workers(const Args& args) {
  const long long n = args.integer("workers", 1);
  DASH_THROW_UNLESS(n >= 1 && n <= 1024, "--workers must be between 1 and 1024");
  return static_cast<int>(n);
}

/// Runs the batch in `runner` (already started) to its end, with Ctrl-C wired to cancel().
int driveToEnd(batch::BatchRunner& runner, batch::ProgressPrinter& printer, const std::string& db_path) {
  g_runner = &runner;
  struct sigaction sa {};
  sa.sa_handler = onInterrupt;
  sigemptyset(&sa.sa_mask);
  struct sigaction old_int {
  }, old_term{};
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  const batch::BatchResult result = runner.wait();
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  g_runner = nullptr;
  printer.finish();

  const batch::BatchProgress& p = result.progress;
  std::printf("batch %s: %s  %lld/%lld runs done: %lld solved, %lld timeout, %lld infeasible, %lld crashed",
              result.batch_id.c_str(), result.status.c_str(), static_cast<long long>(p.done),
              static_cast<long long>(p.total), static_cast<long long>(p.solved), static_cast<long long>(p.timeouts),
              static_cast<long long>(p.failed - p.timeouts - p.crashed), static_cast<long long>(p.crashed));
  if (p.cancelled > 0) std::printf(", %lld cancelled", static_cast<long long>(p.cancelled));
  std::printf("  (%s)\n", batch::ProgressPrinter::formatDuration(p.elapsed).c_str());
  if (result.status != "finished") {
    if (!result.error.empty()) std::fprintf(stderr, "dashbench batch: runner failed: %s\n", result.error.c_str());
    std::printf("resume with: dashbench batch resume --db %s %s\n", db_path.c_str(), result.batch_id.c_str());
  }
  if (result.status == "finished") return kExitOk;
  return result.status == "cancelled" ? 130 : kExitProblems;
}

int runPlanCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"max-runs"}, .flags = {}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch plan needs exactly one spec FILE");
  const batch::BatchSpec spec = batch::loadBatchSpec(args.positional()[0], {.max_runs = maxRuns(args)});
  std::fputs(batch::formatRunList(spec, batch::expandRuns(spec)).c_str(), stdout);
  return kExitOk;
}

int runRunCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"db", "workers", "max-runs", "id"}, .flags = {"quiet"}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch run needs exactly one spec FILE");
  const std::string db_path = args.require("db");
  const batch::BatchSpec spec = batch::loadBatchSpec(args.positional()[0], {.max_runs = maxRuns(args)});
  batch::RunnerOptions options;
  options.workers = workers(args);
  options.batch_id = args.get("id", batch::newBatchId(spec.name));
  batch::ProgressPrinter printer(stderr, batch::ProgressPrinter::autoMode(stderr, args.has("quiet")));
  std::fprintf(stderr, "batch %s: %zu runs, %d worker%s, into %s\n", options.batch_id.c_str(), batch::countRuns(spec),
               options.workers, options.workers == 1 ? "" : "s", db_path.c_str());
  batch::BatchRunner runner;
  runner.start(spec, db_path, options, std::ref(printer));
  return driveToEnd(runner, printer, db_path);
}

int runResumeCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"db", "workers"}, .flags = {"quiet", "force"}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch resume needs exactly one BATCH_ID");
  const std::string db_path = args.require("db");
  batch::RunnerOptions options;
  options.workers = workers(args);
  options.force_resume = args.has("force");
  batch::ProgressPrinter printer(stderr, batch::ProgressPrinter::autoMode(stderr, args.has("quiet")));
  // The first callback comes before any run starts: the header goes there, ahead of progress lines.
  std::once_flag header;
  auto progress = [&](const batch::BatchProgress& p) {
    std::call_once(header, [&] {
      std::fprintf(stderr, "batch %s: resuming %lld of %lld runs (%lld already done), %d worker%s\n",
                   p.batch_id.c_str(), static_cast<long long>(p.total - p.skipped), static_cast<long long>(p.total),
                   static_cast<long long>(p.skipped), options.workers, options.workers == 1 ? "" : "s");
    });
    printer(p);
  };
  batch::BatchRunner runner;
  runner.resume(args.positional()[0], db_path, options, progress);
  return driveToEnd(runner, printer, db_path);
}

int runStatusCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"db"}, .flags = {}});
  DASH_THROW_UNLESS(args.positional().size() <= 1, "batch status takes at most one BATCH_ID");
  const std::string id = args.positional().empty() ? "" : args.positional()[0];
  std::fputs(batch::formatBatchInfo(batch::listBatchInfo(args.require("db"), id)).c_str(), stdout);
  return kExitOk;
}

}  // namespace

int runBatch(const std::vector<std::string>& words) {
  DASH_THROW_UNLESS(!words.empty(), "batch needs a subcommand: plan, run, resume or status (see --help)");
  const std::string sub = words[0];
  const std::vector<std::string> rest(words.begin() + 1, words.end());
  try {
    if (sub == "plan") return runPlanCommand(rest);
    if (sub == "run") return runRunCommand(rest);
    if (sub == "resume") return runResumeCommand(rest);
    if (sub == "status") return runStatusCommand(rest);
  } catch (const log::DbError& e) {
    std::fprintf(stderr, "dashbench batch %s: database error: %s\n", sub.c_str(), e.what());
    return kExitProblems;
  }
  throw InputError("unknown batch subcommand '" + sub + "' (plan, run, resume, status)");
}

}  // namespace dash::cli
