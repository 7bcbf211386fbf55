#pragma once
// The runs table of the API: which columns a client may show, filter and sort on, and the SQL each
// one reads from dash_runs (alias r) joined with its planner configuration (alias c). Scenario
// parameters (robots, objects, walls, ...) are columns too, read from the run's params JSON. Only
// names from this list ever reach SQL text; values are always bound.
#include <string>
#include <vector>

#include "engine/log/results_db.h"

namespace dash::http {

enum class ColumnType { kText, kInteger, kReal };

struct RunColumn {
  std::string name;  ///< the API's name: "planner", "total_time", "robots"
  std::string sql;   ///< expression over r and c
  ColumnType type = ColumnType::kText;
  std::string label;   ///< for people, with the unit: "total time (s)"
  std::string group;   ///< "run", "param", "time", "size", "count", "outcome"
  bool shown = false;  ///< in the dashboard's default column set
};

class RunTable {
 public:
  /// The fixed columns plus one per scenario parameter found in `db`.
  explicit RunTable(const log::ResultsDb& db);

  const std::vector<RunColumn>& columns() const { return columns_; }
  /// nullptr if there is no such column.
  const RunColumn* find(const std::string& name) const;
  const std::vector<std::string>& parameterNames() const { return params_; }

  /// "expr AS "name", ..." for every column (or the ones named; unknown names throw InputError).
  std::string selectList(const std::vector<std::string>& names = {}) const;
  /// FROM clause with the aliases the expressions use.
  static const char* fromClause();
  /// The JSON of the column list: [{"name", "label", "type", "group", "shown"}].
  std::string columnsJson() const;

  /// json_extract(r.params, '$."name"') for a parameter name of letters, digits, '_', '-', '.'.
  static std::string parameterExpression(const std::string& name);

 private:
  std::vector<RunColumn> columns_;
  std::vector<std::string> params_;
};

}  // namespace dash::http
