#include "engine/log/db_query.h"

#include <sqlite3.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>

#include "engine/core/stopwatch.h"

namespace dash::log {
namespace {

constexpr const char* kReadOnlyNote = "; the query console is read-only";
constexpr int kProgressInstructions = 1000;  // VM steps between two time checks
constexpr int kMaxLikePattern = 1000;        // SQLITE_LIMIT_LIKE_PATTERN_LENGTH: LIKE costs cell x pattern
constexpr std::size_t kTableCellWidth = 60;  // wider cells are cut in table output

struct QueryState {
  std::optional<QueryRefused> refused;
  const QueryLimits* limits = nullptr;
  Clock::time_point deadline;
  bool timed_out = false;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

// PRAGMAs that only report: allowed with no argument (or a table / index name for the first group).
const std::set<std::string>& readOnlyPragmas() {
  static const std::set<std::string> names = {
      "table_info", "table_xinfo", "index_list", "index_info", "index_xinfo", "foreign_key_list",
      "foreign_key_check", "integrity_check", "quick_check",
      // the rest only without an argument (with one they would change a setting)
      "user_version", "schema_version", "application_id", "page_count", "page_size", "freelist_count", "encoding",
      "database_list", "collation_list", "function_list", "module_list", "pragma_list", "compile_options",
      "data_version", "journal_mode", "table_list", "max_page_count", "auto_vacuum"};
  return names;
}

bool pragmaTakesName(const std::string& name) {
  static const std::set<std::string> names = {"table_info", "table_xinfo", "index_list", "index_info", "index_xinfo",
                                              "foreign_key_list", "foreign_key_check", "integrity_check",
                                              "quick_check", "table_list"};
  return names.count(name) != 0;
}

QueryRefused writeRefused(const std::string& what) {
  return QueryRefused(QueryGuard::Write, "refused: write statement (" + what + ") is not allowed" + kReadOnlyNote);
}

std::string writeActionName(int code) {
  switch (code) {
    case SQLITE_INSERT: return "INSERT";
    case SQLITE_UPDATE: return "UPDATE";
    case SQLITE_DELETE: return "DELETE";
    case SQLITE_CREATE_INDEX: case SQLITE_CREATE_TEMP_INDEX: return "CREATE INDEX";
    case SQLITE_CREATE_TABLE: case SQLITE_CREATE_TEMP_TABLE: return "CREATE TABLE";
    case SQLITE_CREATE_TRIGGER: case SQLITE_CREATE_TEMP_TRIGGER: return "CREATE TRIGGER";
    case SQLITE_CREATE_VIEW: case SQLITE_CREATE_TEMP_VIEW: return "CREATE VIEW";
    case SQLITE_CREATE_VTABLE: return "CREATE VIRTUAL TABLE";
    case SQLITE_DROP_INDEX: case SQLITE_DROP_TEMP_INDEX: return "DROP INDEX";
    case SQLITE_DROP_TABLE: case SQLITE_DROP_TEMP_TABLE: return "DROP TABLE";
    case SQLITE_DROP_TRIGGER: case SQLITE_DROP_TEMP_TRIGGER: return "DROP TRIGGER";
    case SQLITE_DROP_VIEW: case SQLITE_DROP_TEMP_VIEW: return "DROP VIEW";
    case SQLITE_DROP_VTABLE: return "DROP VIRTUAL TABLE";
    case SQLITE_ALTER_TABLE: return "ALTER TABLE";
    case SQLITE_REINDEX: return "REINDEX";
    case SQLITE_ANALYZE: return "ANALYZE";
    default: return "action " + std::to_string(code);
  }
}

int authorize(void* context, int code, const char* a, const char* b, const char*, const char* view) {
  auto* state = static_cast<QueryState*>(context);
  switch (code) {
    case SQLITE_READ: {
      const std::vector<std::string>& hidden = state->limits->private_tables;
      if (a == nullptr || std::find(hidden.begin(), hidden.end(), lower(a)) == hidden.end()) return SQLITE_OK;
      state->refused =
          QueryRefused(QueryGuard::PrivateTable, "refused: the table " + std::string(a) + " is not readable here" +
                                                     state->limits->private_advice);
      return SQLITE_DENY;
    }
    case SQLITE_SELECT:
    case SQLITE_RECURSIVE:
      return SQLITE_OK;
    case SQLITE_FUNCTION: {
      // fts3_tokenizer('x') returns a native pointer and fts3_tokenizer('x', ptr) installs one.
      // printf/format loop over a width or precision of any size inside one call, where neither
      // the progress handler nor the cell size limit can stop them (400,000,000 ran 16.7 s).
      // The schema's own views use printf with fixed formats: only calls in the query text count.
      const std::string name = lower(b ? b : "");
      const bool refused = name == "fts3_tokenizer" || name == "load_extension" ||
                           (view == nullptr && (name == "printf" || name == "format"));
      if (!refused) return SQLITE_OK;
      state->refused = QueryRefused(QueryGuard::Function, "refused: the function " + name + "() is not allowed" +
                                                              kReadOnlyNote);
      return SQLITE_DENY;
    }
    case SQLITE_UPDATE:
      // Table-valued pragmas (pragma_table_info(...)) ask for UPDATE on the schema table while
      // they compile; nothing is written (the statement is still checked with stmt_readonly).
      if (a != nullptr && (std::string_view(a) == "sqlite_master" || std::string_view(a) == "sqlite_schema")) {
        return SQLITE_OK;
      }
      state->refused = writeRefused("UPDATE");
      return SQLITE_DENY;
    case SQLITE_PRAGMA: {
      const std::string name = lower(a ? a : "");
      if (readOnlyPragmas().count(name) != 0 && (b == nullptr || pragmaTakesName(name))) return SQLITE_OK;
      state->refused = QueryRefused(
          QueryGuard::Pragma, "refused: PRAGMA " + name + (b ? std::string(" = ") + b : std::string()) +
                                  " is not allowed" + kReadOnlyNote +
                                  " (read-only PRAGMAs such as table_info, index_list and user_version are allowed)");
      return SQLITE_DENY;
    }
    case SQLITE_ATTACH:
    case SQLITE_DETACH:
      state->refused = QueryRefused(QueryGuard::Attach, std::string("refused: ") +
                                                            (code == SQLITE_ATTACH ? "ATTACH" : "DETACH") +
                                                            " is not allowed; the query console reads only this database");
      return SQLITE_DENY;
    case SQLITE_TRANSACTION:
    case SQLITE_SAVEPOINT:
      state->refused = QueryRefused(QueryGuard::Transaction,
                                    std::string("refused: transaction control (") + (a ? a : "SAVEPOINT") +
                                        ") is not allowed; each query runs on its own");
      return SQLITE_DENY;
    default:
      state->refused = writeRefused(writeActionName(code));
      return SQLITE_DENY;
  }
}

int progress(void* context) {
  auto* state = static_cast<QueryState*>(context);
  if (Clock::now() < state->deadline) return 0;
  state->timed_out = true;
  return 1;
}

// Skips blanks and SQL comments.
std::size_t skipBlank(const std::string& s, std::size_t i) {
  while (i < s.size()) {
    if (std::isspace(static_cast<unsigned char>(s[i])) || s[i] == ';') {
      ++i;
    } else if (s.compare(i, 2, "--") == 0) {
      i = s.find('\n', i);
      if (i == std::string::npos) return s.size();
    } else if (s.compare(i, 2, "/*") == 0) {
      i = s.find("*/", i + 2);
      if (i == std::string::npos) return s.size();
      i += 2;
    } else {
      break;
    }
  }
  return i;
}

// Refuses by the first keyword: some statements (VACUUM INTO, REINDEX) never reach the authorizer.
void checkFirstKeyword(const std::string& sql) {
  std::size_t i = skipBlank(sql, 0);
  std::size_t end = i;
  while (end < sql.size() && std::isalpha(static_cast<unsigned char>(sql[end]))) ++end;
  const std::string keyword = upper(sql.substr(i, end - i));
  if (keyword.empty()) throw InputError("empty query");
  static const std::set<std::string> reading = {"SELECT", "WITH", "VALUES", "EXPLAIN", "PRAGMA"};
  if (reading.count(keyword) != 0) return;
  if (keyword == "ATTACH" || keyword == "DETACH") {
    throw QueryRefused(QueryGuard::Attach, "refused: " + keyword + " is not allowed; the query console reads only this database");
  }
  static const std::set<std::string> transaction = {"BEGIN", "COMMIT", "END", "ROLLBACK", "SAVEPOINT", "RELEASE"};
  if (transaction.count(keyword) != 0) {
    throw QueryRefused(QueryGuard::Transaction,
                       "refused: transaction control (" + keyword + ") is not allowed; each query runs on its own");
  }
  // Only the statements that write are called write statements; anything else (a misspelled
  // keyword such as SELEC) is left to SQLite, whose syntax error says what is wrong.
  static const std::set<std::string> writing = {"INSERT", "UPDATE", "DELETE",  "REPLACE", "CREATE", "DROP",
                                                "ALTER",  "VACUUM", "REINDEX", "ANALYZE", "UPSERT"};
  if (writing.count(keyword) != 0) throw writeRefused(keyword);
}

std::string numberText(double v) {
  char buffer[32];
  const auto end = std::to_chars(buffer, buffer + sizeof(buffer), v).ptr;
  return std::string(buffer, end);
}

// Exact (shortest round-trip) numbers for CSV; 6 significant digits for people.
std::string cellText(const SqlValue& v, const char* null_text, bool for_people = false) {
  if (std::holds_alternative<std::monostate>(v)) return null_text;
  if (const auto* i = std::get_if<std::int64_t>(&v)) return std::to_string(*i);
  if (const auto* d = std::get_if<double>(&v)) {
    if (!for_people) return numberText(*d);
    char buffer[32];
    const auto end = std::to_chars(buffer, buffer + sizeof(buffer), *d, std::chars_format::general, 6).ptr;
    return std::string(buffer, end);
  }
  return std::get<std::string>(v);
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

/// The bytes of `text` as a JSON string: quotes, and escapes as nlohmann::json writes them.
std::int64_t jsonStringBytes(const std::string& text) {
  std::int64_t n = static_cast<std::int64_t>(text.size()) + 2;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\' || c == '\b' || c == '\f' || c == '\n' || c == '\r' || c == '\t') {
      n += 1;
    } else if (u < 0x20) {
      n += 5;
    }
  }
  return n;
}

/// Column `c` of the statement's current row; adds to `bytes` what the cell takes as JSON text (the
/// server's answer): a separator, the number's digits, a string's quotes and escapes (a control
/// character is 6 bytes as \u0001).
SqlValue readCell(sqlite3_stmt* st, int c, std::int64_t& bytes) {
  bytes += 1;
  switch (sqlite3_column_type(st, c)) {
    case SQLITE_INTEGER: {
      const auto v = static_cast<std::int64_t>(sqlite3_column_int64(st, c));
      bytes += static_cast<std::int64_t>(std::to_string(v).size());
      return v;
    }
    case SQLITE_FLOAT: {
      const double v = sqlite3_column_double(st, c);
      const std::string digits = numberText(v);  // shortest round-trip, as the JSON writer's
      bytes += static_cast<std::int64_t>(digits.size()) +
               (digits.find_first_of(".en") == std::string::npos ? 2 : 0);  // 1 is written 1.0
      return v;
    }
    case SQLITE_TEXT: {
      const int n = sqlite3_column_bytes(st, c);
      std::string text(reinterpret_cast<const char*>(sqlite3_column_text(st, c)), static_cast<std::size_t>(n));
      bytes += jsonStringBytes(text);
      return text;
    }
    case SQLITE_BLOB: {
      std::string text = "<blob " + std::to_string(sqlite3_column_bytes(st, c)) + " bytes>";
      bytes += jsonStringBytes(text);
      return text;
    }
    default:
      bytes += 4;  // null
      return std::monostate{};
  }
}

std::string fit(std::string s) {
  std::replace(s.begin(), s.end(), '\n', ' ');
  if (s.size() > kTableCellWidth) s = s.substr(0, kTableCellWidth - 3) + "...";
  return s;
}

}  // namespace

QueryRefused timeLimitRefused(double seconds, const std::string& advice) {
  return QueryRefused(QueryGuard::TimeLimit,
                      "refused: the query ran past the time limit of " + numberText(seconds) + " s" + advice);
}

SqlRows runReadOnlyQuery(const std::string& path, const std::string& sql, const QueryLimits& limits) {
  DASH_THROW_UNLESS(std::filesystem::is_regular_file(path), "no database file at " + path);
  DASH_THROW_UNLESS(limits.max_rows >= 0, "the row limit must not be negative");
  DASH_THROW_UNLESS(limits.timeout_seconds > 0, "the time limit must be positive");
  DASH_THROW_UNLESS(limits.max_cell_bytes > 0 && limits.max_columns > 0, "the size limits must be positive");
  checkFirstKeyword(sql);

  sql::Connection connection = sql::open(path, SQLITE_OPEN_READONLY | SQLITE_OPEN_NOMUTEX);
  sqlite3* db = connection.get();
  sqlite3_busy_timeout(db, static_cast<int>(std::min(limits.timeout_seconds, 60.0) * 1000));
  sqlite3_limit(db, SQLITE_LIMIT_LENGTH, limits.max_cell_bytes);
  sqlite3_limit(db, SQLITE_LIMIT_COLUMN, limits.max_columns);
  sqlite3_limit(db, SQLITE_LIMIT_LIKE_PATTERN_LENGTH, kMaxLikePattern);
  sqlite3_limit(db, SQLITE_LIMIT_ATTACHED, 0);
  sql::exec(db, "PRAGMA query_only = 1");

  QueryState state;
  state.limits = &limits;
  state.deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                      std::chrono::duration<double>(limits.timeout_seconds));
  sqlite3_set_authorizer(db, authorize, &state);
  sqlite3_progress_handler(db, kProgressInstructions, progress, &state);

  sqlite3_stmt* raw = nullptr;
  const char* tail = nullptr;
  const int rc = sqlite3_prepare_v2(db, sql.c_str(), static_cast<int>(sql.size()), &raw, &tail);
  if (rc != SQLITE_OK) {
    sqlite3_finalize(raw);
    if (state.refused) throw *state.refused;
    if (state.timed_out) throw timeLimitRefused(limits.timeout_seconds, limits.time_limit_advice);
    throw InputError(std::string("SQL error: ") + sqlite3_errmsg(db));
  }
  if (raw == nullptr) throw InputError("empty query");
  std::unique_ptr<sqlite3_stmt, int (*)(sqlite3_stmt*)> stmt(raw, sqlite3_finalize);
  const std::string rest(tail ? tail : "");
  if (skipBlank(rest, 0) < rest.size()) {
    throw QueryRefused(QueryGuard::OneStatement,
                       "refused: more than one statement; the query console runs one statement at a time");
  }
  if (!sqlite3_stmt_readonly(raw)) throw writeRefused(upper(std::string(sql.substr(skipBlank(sql, 0), 6))));

  SqlRows out;
  const int columns = sqlite3_column_count(raw);
  for (int c = 0; c < columns; ++c) out.columns.emplace_back(sqlite3_column_name(raw, c));
  std::int64_t bytes = 0;  // the cells' text read so far
  while (true) {
    const int step = sqlite3_step(raw);
    if (step == SQLITE_DONE) break;
    if (step != SQLITE_ROW) {
      if (state.timed_out) {
        throw timeLimitRefused(limits.timeout_seconds, limits.time_limit_advice);
      }
      throw InputError(std::string("SQL error: ") + sqlite3_errmsg(db));
    }
    if (static_cast<std::int64_t>(out.rows.size()) >= limits.max_rows) {
      out.truncated = true;
      break;
    }
    // The byte budget is checked cell by cell, so one wide row (50 columns of 4 MB) cannot pass it
    // by more than one cell: the cell that crosses it is the last one read. A row complete with
    // that cell is kept, a row cut short is left out whole; the answer stops there (truncated).
    std::vector<SqlValue> row;
    row.reserve(static_cast<std::size_t>(columns));
    bool over_budget = false;
    for (int c = 0; c < columns && !over_budget; ++c) {
      row.push_back(readCell(raw, c, bytes));
      over_budget = limits.max_result_bytes > 0 && bytes > limits.max_result_bytes;
    }
    if (over_budget) {
      if (static_cast<int>(row.size()) == columns) out.rows.push_back(std::move(row));
      out.truncated = true;
      break;
    }
    out.rows.push_back(std::move(row));
  }
  return out;
}

OutputFormat parseOutputFormat(const std::string& name) {
  if (name == "table") return OutputFormat::Table;
  if (name == "csv") return OutputFormat::Csv;
  if (name == "json") return OutputFormat::Json;
  throw InputError("unknown format '" + name + "' (table, csv or json)");
}

std::string formatRows(const SqlRows& rows, OutputFormat format) {
  std::string out;
  if (format == OutputFormat::Csv) {
    for (std::size_t c = 0; c < rows.columns.size(); ++c) {
      if (c != 0) out += ',';
      out += csvField(rows.columns[c]);
    }
    out += '\n';
    for (const auto& row : rows.rows) {
      for (std::size_t c = 0; c < row.size(); ++c) {
        if (c != 0) out += ',';
        out += csvField(cellText(row[c], ""));
      }
      out += '\n';
    }
    return out;
  }
  if (format == OutputFormat::Json) {
    nlohmann::json array = nlohmann::json::array();
    for (const auto& row : rows.rows) {
      nlohmann::json object = nlohmann::json::object();
      for (std::size_t c = 0; c < row.size(); ++c) {
        const SqlValue& v = row[c];
        nlohmann::json& cell = object[rows.columns[c]];
        if (const auto* i = std::get_if<std::int64_t>(&v)) cell = *i;
        else if (const auto* d = std::get_if<double>(&v)) cell = std::isfinite(*d) ? nlohmann::json(*d) : nlohmann::json();
        else if (const auto* s = std::get_if<std::string>(&v)) cell = *s;
      }
      array.push_back(std::move(object));
    }
    return array.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  }
  // Table: columns padded to their widest (cut) cell.
  std::vector<std::vector<std::string>> cells;
  std::vector<std::size_t> widths;
  for (const auto& name : rows.columns) widths.push_back(fit(name).size());
  for (const auto& row : rows.rows) {
    auto& line = cells.emplace_back();
    for (std::size_t c = 0; c < row.size(); ++c) {
      line.push_back(fit(cellText(row[c], "NULL", true)));
      widths[c] = std::max(widths[c], line.back().size());
    }
  }
  auto emit = [&](const std::vector<std::string>& line) {
    std::string text;
    for (std::size_t c = 0; c < line.size(); ++c) {
      if (c != 0) text += " | ";
      text += line[c];
      if (c + 1 < line.size()) text.append(widths[c] - line[c].size(), ' ');
    }
    out += text + "\n";
  };
  std::vector<std::string> header;
  for (const auto& name : rows.columns) header.push_back(fit(name));
  emit(header);
  std::string rule;
  for (std::size_t c = 0; c < widths.size(); ++c) {
    if (c != 0) rule += "-+-";
    rule.append(widths[c], '-');
  }
  out += rule + "\n";
  for (const auto& line : cells) emit(line);
  out += '(';
  out += std::to_string(rows.rows.size());
  out += rows.rows.size() == 1 ? " row" : " rows";
  if (rows.truncated) out += "; stopped by the row limit";
  out += ")\n";
  return out;
}

}  // namespace dash::log
