#pragma once
// Lists of runs for the API: filtered (run_filter.h), sorted, paged; as JSON for the table or as CSV
// for export. Every call opens the results database read-only (WAL: it sees every committed run
// while a batch writes).
#include <cstdint>
#include <string>
#include <vector>

namespace dash::http {

struct RunListRequest {
  std::string filter;              ///< text filter (run_filter.h)
  std::string batch_id;            ///< only this batch's runs
  std::vector<std::string> uuids;  ///< only these runs
  std::string sort = "id";         ///< a column name
  bool descending = true;
  std::int64_t limit = 100;
  std::int64_t offset = 0;
  std::vector<std::string> columns;  ///< CSV only: the columns to write (empty: every column)
};

class RunQueries {
 public:
  explicit RunQueries(std::string db_path) : db_path_(std::move(db_path)) {}

  /// {"total", "offset", "limit", "sort", "order", "runs": [{column: value}]}
  std::string listJson(const RunListRequest& request) const;
  /// RFC 4180 CSV with a header row; at most `max_rows` rows.
  std::string csv(const RunListRequest& request, std::int64_t max_rows) const;
  /// {"columns": [...], "parameters": [...]}: what the table and the filter may use.
  std::string columnsJson() const;

 private:
  std::string db_path_;
};

}  // namespace dash::http
