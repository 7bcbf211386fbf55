#pragma once
// The runs table's text filter, as typed in the dashboard:
//   planner = lazy-dash and robots >= 8 and status = solved
//   config ~ task and total_time < 2.5 and tag = baseline
// Clauses are FIELD OP VALUE joined by "and" and "or" (any case; "and" binds tighter), grouped with
// parentheses (at most 16 deep), at most 64 clauses. Operators: = != < <= > >= and ~ / !~
// (contains / does not contain, for text). FIELD is a column of RunTable (scenario parameters
// included) or "tag". VALUE is a number, a bare word (lazy-dash) or a quoted string. Numeric columns
// compare numbers; a value that is not one is an error. The result is SQL over RunTable's aliases
// with every value bound as a parameter.
#include <string>
#include <vector>

#include "engine/log/sqlite_util.h"
#include "server/http/run_table.h"

namespace dash::http {

struct SqlCondition {
  std::string sql;                    ///< "" when there is nothing to filter
  std::vector<log::SqlValue> params;  ///< bound in order

  /// Appends `other` with AND.
  void andWith(const SqlCondition& other);
  void andWith(const std::string& sql, std::vector<log::SqlValue> params = {});
};

/// Parses the filter; throws InputError with the position and a hint ("unknown field 'robot' (columns:
/// ...)", "expected an operator after 'robots'").
SqlCondition parseRunFilter(const std::string& text, const RunTable& table);

}  // namespace dash::http
