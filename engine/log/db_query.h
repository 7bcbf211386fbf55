#pragma once
// The read-only query console behind `dashbench db query` and the server's query endpoint.
//
// Guards, each named in the error it raises:
// - the file is opened with SQLITE_OPEN_READONLY (and PRAGMA query_only);
// - an authorizer refuses writes (INSERT, UPDATE, DELETE, CREATE, DROP, ALTER, ...), ATTACH and
//   DETACH, transaction control, and PRAGMAs other than a list of read-only ones;
// - statements the authorizer never sees (VACUUM INTO, REINDEX) are refused by their first
//   keyword and by sqlite3_stmt_readonly;
// - one statement per query;
// - a progress handler stops a query that runs past the time limit; a low cell size limit
//   (SQLITE_LIMIT_LENGTH) bounds what one function call can build, which the progress handler
//   cannot interrupt (printf('%.*c', 400000000, 'x') ran 16.7 s under a 64 MB limit);
// - fts3_tokenizer (it reveals and takes raw pointers), load_extension, and printf/format (their
//   width and precision loop inside one call) are refused;
// - tables the caller names private (QueryLimits::private_tables) cannot be read, not even by a view;
// - a row limit and a byte limit stop the output early (reported as truncated, not as an error).
#include <cstdint>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "engine/log/sqlite_util.h"

namespace dash::log {

enum class QueryGuard { Write, Attach, Pragma, Transaction, OneStatement, TimeLimit, Function, PrivateTable };

/// A query refused by a guard, or stopped by the time limit. The message says which.
class QueryRefused : public InputError {
 public:
  QueryRefused(QueryGuard guard, const std::string& message) : InputError(message), guard_(guard) {}
  QueryGuard guard() const { return guard_; }

 private:
  QueryGuard guard_;
};

/// The time-limit refusal: "refused: the query ran past the time limit of SECONDS s" then `advice`.
QueryRefused timeLimitRefused(double seconds, const std::string& advice = "");

struct QueryLimits {
  std::int64_t max_rows = 1000;
  double timeout_seconds = 10.0;
  int max_cell_bytes = 64 << 20;      ///< SQLITE_LIMIT_LENGTH: a longer string or blob is an SQL error
  int max_columns = 2000;             ///< SQLITE_LIMIT_COLUMN
  /// Stop (truncated) once the cells read add up to more, as JSON text (quotes, escapes, digits),
  /// checked cell by cell: the answer holds at most this plus one cell; a row cut short is left
  /// out. 0: none.
  std::int64_t max_result_bytes = 0;
  /// Ends the time-limit refusal: how to raise the limit in the program that runs the query.
  std::string time_limit_advice = "; narrow it or raise the limit (--timeout)";
  /// Tables the query may not read (QueryGuard::PrivateTable), and what the refusal adds: the
  /// server's token-free console cannot read who dispatched from where (GET /api/dispatches needs
  /// the token).
  std::vector<std::string> private_tables;
  std::string private_advice;
};

/// Runs one read-only SQL statement on the file at `path`. Throws QueryRefused for a guard,
/// InputError for SQL errors (syntax, unknown table) and DbError if the file cannot be opened.
SqlRows runReadOnlyQuery(const std::string& path, const std::string& sql, const QueryLimits& limits = {});

enum class OutputFormat { Table, Csv, Json };
/// "table", "csv" or "json"; throws InputError otherwise.
OutputFormat parseOutputFormat(const std::string& name);

/// Text for a terminal (aligned columns, long cells cut), CSV (RFC 4180) or JSON (an array of
/// objects; numbers stay numbers).
std::string formatRows(const SqlRows& rows, OutputFormat format);

}  // namespace dash::log
