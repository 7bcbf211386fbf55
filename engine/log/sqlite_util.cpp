#include "engine/log/sqlite_util.h"

#include <sqlite3.h>

namespace dash::log::sql {

void CloseConnection::operator()(sqlite3* db) const { sqlite3_close_v2(db); }

Connection open(const std::string& path, int flags) {
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags, nullptr);
  Connection db(raw);
  if (rc != SQLITE_OK) {
    throw DbError("cannot open database " + path + ": " + (raw ? sqlite3_errmsg(raw) : sqlite3_errstr(rc)));
  }
  sqlite3_extended_result_codes(raw, 1);
  return db;
}

void fail(sqlite3* db, const std::string& what) {
  throw DbError(what + ": " + sqlite3_errmsg(db) + " (" + sqlite3_db_filename(db, "main") + ")");
}

void exec(sqlite3* db, const std::string& sql) {
  char* message = nullptr;
  if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    throw DbError("SQL failed: " + text + " (in: " + sql.substr(0, 120) + ")");
  }
}

std::string quoteIdentifier(std::string_view name) {
  std::string out = "\"";
  for (char c : name) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

Statement::Statement(sqlite3* db, std::string_view sql) {
  if (sqlite3_prepare_v3(db, sql.data(), static_cast<int>(sql.size()), SQLITE_PREPARE_PERSISTENT, &stmt_,
                         nullptr) != SQLITE_OK) {
    fail(db, "cannot prepare '" + std::string(sql.substr(0, 120)) + "'");
  }
}

Statement::~Statement() { sqlite3_finalize(stmt_); }

Statement::Statement(Statement&& other) noexcept : stmt_(other.stmt_) { other.stmt_ = nullptr; }

Statement& Statement::operator=(Statement&& other) noexcept {
  if (this != &other) {
    sqlite3_finalize(stmt_);
    stmt_ = other.stmt_;
    other.stmt_ = nullptr;
  }
  return *this;
}

static void checkBind(sqlite3_stmt* stmt, int rc) {
  if (rc != SQLITE_OK) fail(sqlite3_db_handle(stmt), "cannot bind a parameter");
}

Statement& Statement::bind(int i, std::int64_t v) {
  checkBind(stmt_, sqlite3_bind_int64(stmt_, i, v));
  return *this;
}
Statement& Statement::bind(int i, double v) {
  checkBind(stmt_, sqlite3_bind_double(stmt_, i, v));
  return *this;
}
Statement& Statement::bind(int i, std::string_view v) {
  checkBind(stmt_, sqlite3_bind_text64(stmt_, i, v.data(), v.size(), SQLITE_TRANSIENT, SQLITE_UTF8));
  return *this;
}
Statement& Statement::bindStatic(int i, std::string_view v) {
  checkBind(stmt_, sqlite3_bind_text64(stmt_, i, v.data(), v.size(), SQLITE_STATIC, SQLITE_UTF8));
  return *this;
}
Statement& Statement::bindNull(int i) {
  checkBind(stmt_, sqlite3_bind_null(stmt_, i));
  return *this;
}
Statement& Statement::bind(int i, const SqlValue& v) {
  if (const auto* n = std::get_if<std::int64_t>(&v)) return bind(i, *n);
  if (const auto* d = std::get_if<double>(&v)) return bind(i, *d);
  if (const auto* s = std::get_if<std::string>(&v)) return bind(i, std::string_view(*s));
  return bindNull(i);
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  sqlite3* db = sqlite3_db_handle(stmt_);
  const std::string sql = sqlite3_sql(stmt_) ? sqlite3_sql(stmt_) : "";
  sqlite3_reset(stmt_);
  fail(db, "statement failed ('" + sql.substr(0, 80) + "')");
}

void Statement::run() {
  while (step()) {
  }
  reset();
}

void Statement::runKeepingBindings() {
  while (step()) {
  }
  sqlite3_reset(stmt_);
}

void Statement::reset() {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

int Statement::columnCount() const { return sqlite3_column_count(stmt_); }
std::string Statement::columnName(int i) const { return sqlite3_column_name(stmt_, i); }
bool Statement::isNull(int i) const { return sqlite3_column_type(stmt_, i) == SQLITE_NULL; }
std::int64_t Statement::columnInt(int i) const { return sqlite3_column_int64(stmt_, i); }
double Statement::columnDouble(int i) const { return sqlite3_column_double(stmt_, i); }

std::string Statement::columnText(int i) const {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, i));
  return text ? std::string(text, static_cast<std::size_t>(sqlite3_column_bytes(stmt_, i))) : std::string();
}

std::optional<std::int64_t> Statement::columnOptInt(int i) const {
  if (isNull(i)) return std::nullopt;
  return columnInt(i);
}

std::optional<double> Statement::columnOptDouble(int i) const {
  if (isNull(i)) return std::nullopt;
  return columnDouble(i);
}

SqlValue Statement::columnValue(int i) const {
  switch (sqlite3_column_type(stmt_, i)) {
    case SQLITE_INTEGER: return columnInt(i);
    case SQLITE_FLOAT: return columnDouble(i);
    case SQLITE_TEXT: return columnText(i);
    case SQLITE_BLOB: return "<blob " + std::to_string(sqlite3_column_bytes(stmt_, i)) + " bytes>";
    default: return std::monostate{};
  }
}

SqlRows selectRows(sqlite3* db, std::string_view sql, const std::vector<SqlValue>& params) {
  Statement st(db, sql);
  for (std::size_t i = 0; i < params.size(); ++i) st.bind(static_cast<int>(i) + 1, params[i]);
  SqlRows out;
  for (int c = 0; c < st.columnCount(); ++c) out.columns.push_back(st.columnName(c));
  while (st.step()) {
    std::vector<SqlValue>& row = out.rows.emplace_back();
    row.reserve(out.columns.size());
    for (int c = 0; c < st.columnCount(); ++c) row.push_back(st.columnValue(c));
  }
  return out;
}

std::int64_t selectInt(sqlite3* db, std::string_view sql, std::int64_t fallback) {
  Statement st(db, sql);
  if (!st.step() || st.isNull(0)) return fallback;
  return st.columnInt(0);
}

}  // namespace dash::log::sql
