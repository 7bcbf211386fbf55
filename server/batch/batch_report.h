#pragma once
// `dashbench report`: the tables behind the paper's comparisons, from a results database. Per
// scenario family, one row per (parameters, planner configuration), medians across seeds:
//   - representation sizes: vertices and hyperarcs of H_T, H_TE, H_M, H_ME;
//   - time breakdown (phase totals): task construction, task query, task conflict detection,
//     motion construction, motion query, conflict resolution, total;
//   - success rate: solved / finished runs, with timeouts, infeasible and crashed runs.
// With a batch: the runs the axis stop rule skipped, and where each planner breaks along each stop
// axis (the largest size every seed solved, the largest some seed solved, the first size no seed
// solved, the first size skipped).
// Sizes and times are medians over the row's solved runs (over every finished run with
// include_unsolved). Runs still running or cancelled are left out.
#include <string>

#include "engine/log/results_db.h"

namespace dash::batch {

struct ReportOptions {
  std::string batch_id;           ///< empty: every run of the file
  bool include_unsolved = false;  ///< medians over timeout and infeasible runs too
};

std::string formatReport(const log::ResultsDb& db, const ReportOptions& options = {});

/// The median of `values` (the mean of the middle two for an even count); NaN when empty.
double median(std::vector<double> values);

}  // namespace dash::batch
