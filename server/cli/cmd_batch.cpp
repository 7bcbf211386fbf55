// dashbench batch plan|run|resume|status: experiment batches from spec files (experiments/*.json).
// The runner is server/batch's BatchRunner, the same one the server uses.
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <map>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include "engine/log/results_db.h"
#include "server/batch/batch_runner.h"
#include "server/batch/batch_spec.h"
#include "server/batch/batch_store.h"
#include "server/batch/progress_printer.h"
#include "server/batch/slurm_backend.h"
#include "server/batch/slurm_task.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kBatchHelp;
const char* const kBatchHelp =
    "usage: dashbench batch plan FILE [--max-runs N] [--workers N]\n"
    "       dashbench batch run FILE --db DB [--workers N] [--quiet] [--max-runs N] [--id ID]\n"
    "       dashbench batch run FILE --db DB --backend slurm [--partition P] [--account A] [--max-parallel N]\n"
    "                           [--runs-per-task K] [--shard-dir DIR] [--detach] [--poll SEC] [--id ID]\n"
    "       dashbench batch resume --db DB BATCH_ID [--workers N] [--quiet] [--force]\n"
    "       dashbench batch status --db DB [BATCH_ID]\n"
    "       dashbench batch cancel --db DB BATCH_ID\n"
    "Experiment batches: a spec file (see experiments/README.md) is a grid of scenario families and\n"
    "parameters x planner configurations x seeds, with a time and memory limit per run.\n"
    "  plan     validate FILE and print the expanded runs without running them, with an estimate of\n"
    "           the batch's duration with N workers\n"
    "  run      run every run of FILE, each in its own process, into the results database DB\n"
    "           (created if missing). The batch id is printed first; progress goes to stderr.\n"
    "  resume   run what batch BATCH_ID is missing after its runner was killed or cancelled:\n"
    "           runs never started, cancelled, or left 'running' (their partial rows are replaced)\n"
    "  status   list the batches of DB (or one) with their runs per status; for a Slurm batch also\n"
    "           its array tasks per Slurm state (merging the shards of runs that ended)\n"
    "  cancel   cancel a batch: scancel for a Slurm batch, SIGTERM to the runner of a local one\n"
    "Options:\n"
    "  --workers N    runs at once (default 1)\n"
    "  --quiet        no progress on stderr (without a terminal: one line per finished run)\n"
    "  --max-runs N   refuse specs that expand to more runs (default 10000)\n"
    "  --id ID        the new batch's id (default: NAME-yyyymmdd-hhmmss-xxxx)\n"
    "  --force        resume even if the batch's runner seems alive (its heartbeat is fresh)\n"
    "Slurm (--backend slurm; see README.md, \"Running on a Slurm cluster\"): the batch becomes a job\n"
    "array (sbatch); each array task runs its runs like the local runner, into its own SQLite shard in\n"
    "the shard directory, which must be on storage the compute nodes share; this command follows the\n"
    "job (squeue/sacct) and merges the shards into DB as runs end. --time and --mem of each task come\n"
    "from the spec's limits with a margin, --cpus-per-task is 1.\n"
    "  --partition P, --account A   sbatch's options (default: the cluster's)\n"
    "  --max-parallel N  array tasks at once (sbatch --array=0-(N-1)%max-parallel; default: no limit)\n"
    "  --runs-per-task K runs per array task (default 1; raised to keep the array at 1000 tasks)\n"
    "  --shard-dir DIR   where the manifest, job script, shards and logs go (default: DB.slurm/BATCH_ID)\n"
    "  --detach          submit and return; `batch status` merges and `batch resume` resubmits later\n"
    "  --poll SEC        seconds between two looks at Slurm while following (default 10)\n"
    "Ctrl-C stops a batch cleanly: running runs get SIGTERM (then SIGKILL after 2 s) and are recorded\n"
    "as cancelled; a second Ctrl-C kills them at once. Resume it later with `batch resume`. Following a\n"
    "Slurm batch, Ctrl-C cancels its job (scancel) and waits for the cancelled runs to be merged.\n"
    "Exit codes: 0 the batch finished, 2 bad input, 1 the runner failed, 130 cancelled.\n";

namespace {

batch::BatchRunner* g_runner = nullptr;
batch::SlurmTask* g_slurm_task = nullptr;
std::atomic<int> g_slurm_interrupts{0};
extern "C" void onInterrupt(int) {
  if (g_runner != nullptr) g_runner->cancel();
  if (g_slurm_task != nullptr) g_slurm_task->cancel();
  g_slurm_interrupts.fetch_add(1);
}

/// SIGINT and SIGTERM go to onInterrupt while it lives.
class InterruptScope {
 public:
  InterruptScope() {
    struct sigaction sa {};
    sa.sa_handler = onInterrupt;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~InterruptScope() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  struct sigaction old_int_ {};
  struct sigaction old_term_ {};
};

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
  batch::BatchResult result;
  {
    const InterruptScope interrupts;
    result = runner.wait();
  }
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


batch::SlurmSubmitOptions slurmOptions(const Args& args) {
  batch::SlurmSubmitOptions o;
  o.partition = args.get("partition", "");
  o.account = args.get("account", "");
  const long long parallel = args.integer("max-parallel", 0);
  DASH_THROW_UNLESS(parallel >= 0 && parallel <= 100000, "--max-parallel must be between 0 and 100000");
  o.max_parallel = static_cast<int>(parallel);
  const long long per_task = args.integer("runs-per-task", 1);
  DASH_THROW_UNLESS(per_task >= 1 && per_task <= 100000, "--runs-per-task must be between 1 and 100000");
  o.runs_per_task = static_cast<int>(per_task);
  o.shard_dir = args.get("shard-dir", "");
  o.batch_id = args.get("id", "");
  return o;
}

double pollSeconds(const Args& args) {
  const double poll = args.number("poll", 10.0);
  DASH_THROW_UNLESS(poll > 0 && poll <= 3600, "--poll must be between 0 and 3600 seconds");
  return poll;
}

/// The runs of a Slurm batch per status, as the local runner's last line shows them.
std::string slurmRunCounts(const batch::SlurmBatchView& view) {
  std::map<std::string, int> counts;
  for (const auto& [key, status] : view.run_status) ++counts[status.empty() ? "missing" : status];
  std::string out;
  for (const auto& [status, n] : counts) out += (out.empty() ? "" : ", ") + std::to_string(n) + " " + status;
  return out;
}

/// Follows a Slurm batch until no array task is pending or running, merging shards as they change.
/// Ctrl-C cancels the job once (scancel); the loop then waits for the cancelled tasks to end.
int followSlurm(batch::SlurmBackend& backend, const std::string& batch_id, const std::string& db_path, double poll,
                bool quiet) {
  const InterruptScope interrupts;
  g_slurm_interrupts.store(0);
  bool cancelled = false;
  std::string last_line;
  batch::SlurmBatchView view;
  while (true) {
    if (g_slurm_interrupts.load() > 0 && !cancelled) {
      cancelled = true;
      std::fprintf(stderr, "batch %s: cancelling its Slurm job (scancel)\n", batch_id.c_str());
      try {
        backend.cancel(batch_id);
      } catch (const InputError& e) {
        std::fprintf(stderr, "batch %s: %s\n", batch_id.c_str(), e.what());
      }
    }
    view = backend.update(batch_id);
    std::string line = batch::formatSlurmView(view, false);
    if (!quiet && line != last_line) std::fputs(line.c_str(), stderr);
    last_line = std::move(line);
    if (!view.active) break;
    const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(poll);
    while (std::chrono::steady_clock::now() < until && (cancelled || g_slurm_interrupts.load() == 0)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  std::printf("batch %s: %s  %lld/%lld runs with a result: %s\n", batch_id.c_str(), view.status.c_str(),
              static_cast<long long>(view.complete), static_cast<long long>(view.runs), slurmRunCounts(view).c_str());
  if (view.status == "finished") return kExitOk;
  std::printf("resume with: dashbench batch resume --db %s %s\n", db_path.c_str(), batch_id.c_str());
  return view.status == "cancelled" ? 130 : kExitProblems;
}

int runSlurmRun(const Args& args, const std::string& db_path) {
  const batch::BatchSpec spec = batch::loadBatchSpec(args.positional()[0], {.max_runs = maxRuns(args)});
  batch::SlurmSubmitOptions options = slurmOptions(args);
  if (options.batch_id.empty()) options.batch_id = batch::newBatchId(spec.name);
  batch::SlurmBackend backend(db_path);
  const std::string id = backend.submit(spec, options);
  const batch::SlurmBatchView view = backend.update(id);
  std::fprintf(stderr, "batch %s: %zu runs submitted to Slurm as job %s (%zu array tasks), into %s\n", id.c_str(),
               batch::countRuns(spec), view.tasks.empty() ? "?" : view.tasks.front().job_id.c_str(), view.tasks.size(),
               db_path.c_str());
  if (args.has("detach")) {
    std::printf("batch %s: submitted\nfollow with: dashbench batch status --db %s %s\n", id.c_str(), db_path.c_str(),
                id.c_str());
    return kExitOk;
  }
  return followSlurm(backend, id, db_path, pollSeconds(args), args.has("quiet"));
}

int runPlanCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"max-runs", "workers"}, .flags = {}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch plan needs exactly one spec FILE");
  const batch::BatchSpec spec = batch::loadBatchSpec(args.positional()[0], {.max_runs = maxRuns(args)});
  std::fputs(batch::formatRunList(spec, batch::expandRuns(spec), workers(args)).c_str(), stdout);
  return kExitOk;
}

int runRunCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"db", "workers", "max-runs", "id", "backend", "partition", "account", "max-parallel",
                                 "runs-per-task", "shard-dir", "poll"},
                     .flags = {"quiet", "detach"}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch run needs exactly one spec FILE");
  const std::string db_path = args.require("db");
  const std::string backend = args.get("backend", "local");
  DASH_THROW_UNLESS(backend == "local" || backend == "slurm", "--backend must be local or slurm");
  if (backend == "slurm") return runSlurmRun(args, db_path);
  for (const char* slurm_only : {"partition", "account", "max-parallel", "runs-per-task", "shard-dir", "poll", "detach"}) {
    DASH_THROW_UNLESS(!args.has(slurm_only), std::string("--") + slurm_only + " is for --backend slurm");
  }
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
  Args args(words, {.options = {"db", "workers", "partition", "account", "max-parallel", "runs-per-task", "poll"},
                     .flags = {"quiet", "force", "detach"}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch resume needs exactly one BATCH_ID");
  const std::string db_path = args.require("db");
  if (batch::SlurmBackend::isSlurmBatch(db_path, args.positional()[0])) {
    const std::string id = args.positional()[0];
    batch::SlurmBackend backend(db_path);
    const std::int64_t n = backend.resume(id, slurmOptions(args));
    std::fprintf(stderr, "batch %s: %lld missing runs resubmitted to Slurm\n", id.c_str(), static_cast<long long>(n));
    if (args.has("detach")) return kExitOk;
    return followSlurm(backend, id, db_path, pollSeconds(args), args.has("quiet"));
  }
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
  const std::string db_path = args.require("db");
  // A Slurm batch still in Slurm is brought up to date first: its tasks' states, and the shards of
  // the runs that ended merged (this needs write access to DB).
  std::vector<batch::SlurmBatchView> views;
  for (const batch::BatchInfo& info : batch::listBatchInfo(db_path, id)) {
    if (!batch::SlurmBackend::isSlurmBatch(db_path, info.record.id)) continue;
    views.push_back(batch::SlurmBackend(db_path).update(info.record.id));
  }
  std::fputs(batch::formatBatchInfo(batch::listBatchInfo(db_path, id)).c_str(), stdout);
  for (const batch::SlurmBatchView& view : views) std::fputs(batch::formatSlurmView(view, !id.empty()).c_str(), stdout);
  return kExitOk;
}

int runCancelCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"db"}, .flags = {}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "batch cancel needs exactly one BATCH_ID");
  const std::string db_path = args.require("db");
  const std::string id = args.positional()[0];
  if (batch::SlurmBackend::isSlurmBatch(db_path, id)) {
    batch::SlurmBackend backend(db_path);
    backend.cancel(id);
    std::printf("batch %s: Slurm job cancelled (scancel); `batch status` merges what its runs recorded\n", id.c_str());
    return kExitOk;
  }
  const std::vector<batch::BatchInfo> infos = batch::listBatchInfo(db_path, id);
  const auto& runner = infos.front().runner;
  DASH_THROW_UNLESS(infos.front().record.status == "running" && runner && runner->alive(),
                    "batch " + id + " is not running");
  char host[256] = {};
  gethostname(host, sizeof host - 1);
  DASH_THROW_UNLESS(runner->host == host, "batch " + id + " runs on " + runner->host + ": cancel it there");
  DASH_THROW_UNLESS(kill(static_cast<pid_t>(runner->pid), SIGTERM) == 0,
                    "cannot signal the runner (process " + std::to_string(runner->pid) + ")");
  std::printf("batch %s: SIGTERM sent to its runner (process %lld)\n", id.c_str(), static_cast<long long>(runner->pid));
  return kExitOk;
}

/// One array task of a Slurm batch (the job script's command; not for people).
int runSlurmTaskCommand(const std::vector<std::string>& words) {
  Args args(words, {.options = {"manifest", "task", "work-dir"}, .flags = {}});
  const long long task = args.integer("task", -1);
  DASH_THROW_UNLESS(task >= 0 && task <= 1000000, "--task must be the array task's index");
  batch::SlurmTask slurm_task({.manifest = args.require("manifest"),
                               .task = static_cast<int>(task),
                               .executable = "",
                               .work_dir = args.get("work-dir", "")});
  g_slurm_task = &slurm_task;
  int code = 0;
  {
    const InterruptScope interrupts;
    code = slurm_task.run();
  }
  g_slurm_task = nullptr;
  return code;
}

}  // namespace

int runBatch(const std::vector<std::string>& words) {
  DASH_THROW_UNLESS(!words.empty(), "batch needs a subcommand: plan, run, resume, status or cancel (see --help)");
  const std::string sub = words[0];
  const std::vector<std::string> rest(words.begin() + 1, words.end());
  try {
    if (sub == "plan") return runPlanCommand(rest);
    if (sub == "run") return runRunCommand(rest);
    if (sub == "resume") return runResumeCommand(rest);
    if (sub == "status") return runStatusCommand(rest);
    if (sub == "cancel") return runCancelCommand(rest);
    if (sub == "slurm-task") return runSlurmTaskCommand(rest);
  } catch (const log::DbError& e) {
    std::fprintf(stderr, "dashbench batch %s: database error: %s\n", sub.c_str(), e.what());
    return kExitProblems;
  }
  throw InputError("unknown batch subcommand '" + sub + "' (plan, run, resume, status, cancel)");
}

}  // namespace dash::cli
