#pragma once
// The terminal side of a batch's progress callback (`dashbench batch run|resume`):
//   bar   : one line redrawn in place on a terminal: a bar, runs done, failed, running and left,
//           an ETA, the conflict-resolution steps of the running runs that are scheduling, and the
//           longest-running run with its time (a DaSH construction of minutes shows which run works);
//           crashed runs also get a line of their own above it;
//   lines : a line per finished run (stderr is not a terminal: logs, CI), every 2 s a line per
//           running run whose planner reports a long phase's progress (conflict resolution's steps),
//           and every 10 s a line per run that has run that long without reporting any;
//   quiet : nothing.
// The ETA is re-estimated when a run ends (the runner's: time per finished run times the runs left)
// and counts down between (SteadyEta), so it never counts up while a long run works.
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>

#include "server/batch/batch_runner.h"

namespace dash::batch {

/// The runner's ETA taken when a run ends, counted down by the batch's clock until the next one ends;
/// unknown (-1) once the countdown ran out with runs still to finish (the current runs take longer
/// than the runs so far did).
class SteadyEta {
 public:
  double operator()(const BatchProgress& p);

 private:
  std::int64_t done_ = -1;
  double eta_ = -1.0;
  double at_ = 0.0;
};

class ProgressPrinter {
 public:
  enum class Mode { kBar, kLines, kQuiet };
  /// kQuiet if `quiet`, else kBar when `out` is a terminal, else kLines.
  static Mode autoMode(std::FILE* out, bool quiet);

  ProgressPrinter(std::FILE* out, Mode mode) : out_(out), mode_(mode) {}
  void operator()(const BatchProgress& p);
  /// Ends the bar's line (call after the batch ended).
  void finish();

  /// "[#######.......] 12/40 done  2 failed  2 running  28 left  ETA 1m20s" (`width`: the bar's cells).
  static std::string formatBar(const BatchProgress& p, int width = 24);
  /// "[12/40] solved     sorting/robots=4,objects=8/seed=1/lazy-dash  0.4 s" (+ the error, cut).
  static std::string formatLine(const BatchProgress& p, const FinishedRun& run);
  /// "1h02m", "3m05s", "12s".
  static std::string formatDuration(double seconds);
  /// A running run's long-phase progress: "steps 37/146 (ur5e_3, ur5e_7) 4.2 steps/s"; empty when
  /// it reports none now (never yet, or its last one ended).
  static std::string formatWork(const ActiveRun& run);
  /// "[running]  sorting/robots=4,objects=8/seed=1/lazy-dash  steps 37/146 (ur5e_3) 4.2 steps/s  12 s".
  static std::string formatActiveLine(const ActiveRun& run);

 private:
  std::FILE* out_;
  Mode mode_;
  bool bar_drawn_ = false;
  std::map<std::string, double> active_printed_;  ///< lines mode: uuid -> batch time of its last line
  SteadyEta eta_;
};

}  // namespace dash::batch
