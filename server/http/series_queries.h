#pragma once
// Aggregated series for the Compare page: runs of one scenario family grouped by planner
// configuration (or planner) and by the value of one scenario parameter (the x axis). For each
// group: runs per status and the success rate over finished runs, and for each metric (the four
// representations' vertices and hyperarcs, each phase's time, task / motion / total time, makespan)
// the values across seeds with median, quartiles, minimum and maximum. With `split`, each value of a
// second parameter (robots, say) makes series of its own, as the paper plots them. Values come from solved runs
// only unless include_unsolved (timeouts and infeasible runs have partial figures).
#include <string>

namespace dash::http {

struct SeriesRequest {
  std::string family;               ///< required
  std::string x = "objects";        ///< a scenario parameter of the family
  std::string group_by = "config";  ///< "config" (planner configuration) or "planner"
  std::string split;                ///< another parameter: one series per value ("lazy-dash · robots=4")
  std::string filter;               ///< the runs table's text filter (run_filter.h)
  bool include_unsolved = false;
};

class SeriesQueries {
 public:
  explicit SeriesQueries(std::string db_path) : db_path_(std::move(db_path)) {}

  /// {"family", "x", "group_by", "metrics": [{"name", "label", "unit"}], "groups": [{"group", "x", "runs",
  ///  "finished", "by_status", "success_rate", "metrics": {name: {"n", "values", "median", "q1", "q3",
  ///  "min", "max", "mean"}}}]}; groups sorted by group then x.
  std::string seriesJson(const SeriesRequest& request) const;
  /// {"families": [{"family", "runs", "parameters": [...], "configs": [...]}]}: what there is to compare.
  std::string overviewJson() const;

 private:
  std::string db_path_;
};

}  // namespace dash::http
