// dashbench report: the paper's tables (representation sizes, time breakdown, success rates) from
// a results database, per scenario family, medians across seeds, and paired statistics of every two
// planner configurations that count failures (server/figures/paired_stats.h).
#include <cstdio>
#include <string>

#include "engine/log/results_db.h"
#include "server/figures/comparison_figures.h"
#include "server/batch/batch_report.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

extern const char* const kReportHelp;
const char* const kReportHelp =
    "usage: dashbench report DB [--batch ID] [--all-runs] [--figures DIR [--svg-only]]\n"
    "Per scenario family, one row per (parameters, planner configuration), medians across seeds:\n"
    "  - representation sizes: vertices (V) and hyperarcs (A) of H_T, H_TE, H_M and H_ME;\n"
    "  - time breakdown from the phase totals: task construction, task query, task conflict\n"
    "    detection, motion construction, motion query, conflict resolution, and the total;\n"
    "  - success rate: solved runs of the finished ones, with timeouts, infeasible, out of memory\n"
    "    and crashed, and its 95% Wilson interval;\n"
    "  - paired comparison of every two planner configurations on the same scenes and seeds, per\n"
    "    parameters and over all: the time ratio a/b (geometric mean over the pairs both solved,\n"
    "    95% t interval on the log ratios), a sign test on which solved faster where a run that did\n"
    "    not solve is censored at its time limit (two-sided exact p), and each side's solved pairs\n"
    "    with 95% Wilson intervals (docs/comparison-figures.md);\n"
    "  - with --batch: runs the axis stop rule skipped, and where each planner breaks along each\n"
    "    stop axis (largest size all seeds / some seed solved, first size none solved, skipped from,\n"
    "    every size some seed failed)\n"
    "  --batch ID    only the runs of batch ID (default: every run of DB)\n"
    "  --all-runs    sizes and times over every finished run, not only the solved ones\n"
    "  --figures DIR also write the paper's figures per family into DIR (created if missing):\n"
    "                FAMILY-sizes (H_T, H_M vertices and hyperarcs, log scale), FAMILY-time\n"
    "                (construction, query, conflict resolution, total; one y range), FAMILY-success\n"
    "                (solved %; sizes the axis stop rule skipped as crosses), as SVG and PNG\n"
    "  --svg-only    with --figures: no PNG (PNG needs rsvg-convert, Debian package librsvg2-bin)\n"
    "Runs still running and cancelled runs are left out.\n";

int runReport(const std::vector<std::string>& words) {
  Args args(words, {.options = {"batch", "figures"}, .flags = {"all-runs", "svg-only"}});
  DASH_THROW_UNLESS(args.positional().size() == 1, "report needs exactly one results database DB");
  try {
    const log::ResultsDb db(args.positional()[0], log::OpenMode::ReadOnly);
    if (auto id = args.get("batch")) {
      bool known = false;
      for (const auto& b : db.listBatches()) known |= b.id == *id;
      DASH_THROW_UNLESS(known, "no batch " + *id + " in " + args.positional()[0]);
    }
    const std::string text = batch::formatReport(
        db, batch::ReportOptions{.batch_id = args.get("batch", ""), .include_unsolved = args.has("all-runs")});
    std::fputs(text.c_str(), stdout);
    if (auto dir = args.get("figures")) {
      const figures::FigureFiles files = figures::writeComparisonFigures(
          db, figures::FigureOptions{.batch_id = args.get("batch", ""), .dir = *dir, .png = !args.has("svg-only")});
      std::fprintf(stderr, "dashbench report: wrote %zu figure files for %zu families into %s\n", files.files.size(),
                   files.families.size(), dir->c_str());
    }
  } catch (const log::DbError& e) {
    std::fprintf(stderr, "dashbench report: database error: %s\n", e.what());
    return kExitProblems;
  }
  return kExitOk;
}

}  // namespace dash::cli
