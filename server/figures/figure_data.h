#pragma once
// What the comparison figures plot, read from a results database: per scenario family, the problem
// size axis (objects when they vary, else the parameter with the most values: containers for Lab),
// and one line per (planner configuration, other parameters): its finished runs per size, and the
// sizes the batch's axis stop rule skipped (server/batch/axis_stop.h; read from the batch tables).
#include <map>
#include <string>
#include <vector>

#include "engine/log/results_db.h"

namespace dash::figures {

struct Line {
  std::string planner;  ///< planner configuration name
  std::string group;    ///< the other parameters: "robots=4" (empty when none varies)
  std::map<int, std::vector<const log::RunRecord*>> runs;  ///< size -> finished runs
  std::map<int, int> skipped;                              ///< size -> runs not run
  std::string name() const { return group.empty() ? planner : planner + " " + group; }
};

struct FamilyData {
  std::string family;
  std::string x_param;
  std::vector<Line> lines;  ///< by group, then planner
};

struct FigureRuns {
  std::vector<log::RunRecord> runs;  ///< what the lines point into
  std::vector<FamilyData> families;  ///< in the registry's order
};

/// The finished runs (neither running nor cancelled) of `batch_id` (empty: every run), grouped.
FigureRuns collectFigureRuns(const log::ResultsDb& db, const std::string& batch_id);

}  // namespace dash::figures
