#pragma once
// Thin RAII over SQLite's C API: a connection handle, prepared statements, a value type for
// results, and one error type. Only engine/log includes this header.
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace dash::log {

/// SQLite itself failed (I/O error, disk full, a locked database past busy_timeout). Bad input
/// from a user (a newer schema, a refused query) is an InputError instead.
class DbError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One cell of a result: NULL, integer, real or text (blobs come back as "<blob N bytes>").
using SqlValue = std::variant<std::monostate, std::int64_t, double, std::string>;

struct SqlRows {
  std::vector<std::string> columns;
  std::vector<std::vector<SqlValue>> rows;
  bool truncated = false;  ///< a row limit stopped it early
};

namespace sql {

struct CloseConnection {
  void operator()(sqlite3* db) const;
};
using Connection = std::unique_ptr<sqlite3, CloseConnection>;

/// Opens `path` with SQLITE_OPEN_* `flags`; throws DbError naming the file on failure.
Connection open(const std::string& path, int flags);

[[noreturn]] void fail(sqlite3* db, const std::string& what);

/// Runs one or more statements without results; throws DbError on failure.
void exec(sqlite3* db, const std::string& sql);

/// Quotes an identifier for SQL: "name" with inner quotes doubled.
std::string quoteIdentifier(std::string_view name);

class Statement {
 public:
  Statement() = default;
  Statement(sqlite3* db, std::string_view sql);
  ~Statement();
  Statement(Statement&& other) noexcept;
  Statement& operator=(Statement&& other) noexcept;
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  // Parameters are 1-based, as in SQLite.
  Statement& bind(int i, std::int64_t v);
  Statement& bind(int i, int v) { return bind(i, static_cast<std::int64_t>(v)); }
  Statement& bind(int i, double v);
  Statement& bind(int i, std::string_view v);  ///< copied by SQLite
  Statement& bind(int i, const char* v) { return bind(i, std::string_view(v)); }
  Statement& bind(int i, const std::string& v) { return bind(i, std::string_view(v)); }
  /// Not copied: `v` must stay alive until the statement is reset. For the recorder's hot path.
  Statement& bindStatic(int i, std::string_view v);
  Statement& bindNull(int i);
  Statement& bind(int i, const SqlValue& v);
  template <class T>
  Statement& bind(int i, const std::optional<T>& v) {
    return v ? bind(i, *v) : bindNull(i);
  }
  /// Empty text binds NULL.
  Statement& bindOrNull(int i, std::string_view v) { return v.empty() ? bindNull(i) : bind(i, v); }

  /// Advances one row: true if a row is ready, false when done. Throws DbError on failure.
  bool step();
  /// Steps to the end, then resets (for INSERT/UPDATE).
  void run();
  /// run() without clearing the bindings: for hot statements whose every parameter is bound again
  /// before the next run.
  void runKeepingBindings();
  void reset();

  int columnCount() const;
  std::string columnName(int i) const;
  bool isNull(int i) const;
  std::int64_t columnInt(int i) const;
  double columnDouble(int i) const;
  std::string columnText(int i) const;
  std::optional<std::int64_t> columnOptInt(int i) const;
  std::optional<double> columnOptDouble(int i) const;
  SqlValue columnValue(int i) const;

  sqlite3_stmt* get() const { return stmt_; }

  /// Binds parameters 1, 2, 3... in call order: `auto b = st.binder(); b(x)(y)(z);`.
  class Binder {
   public:
    explicit Binder(Statement& st) : st_(&st) {}
    template <class T>
    Binder& operator()(const T& value) {
      st_->bind(++index_, value);
      return *this;
    }
    Binder& orNull(std::string_view value) {
      st_->bindOrNull(++index_, value);
      return *this;
    }

   private:
    Statement* st_;
    int index_ = 0;
  };
  Binder binder() { return Binder(*this); }

 private:
  sqlite3_stmt* stmt_ = nullptr;
};

/// Runs a SELECT with positional parameters and collects every row.
SqlRows selectRows(sqlite3* db, std::string_view sql, const std::vector<SqlValue>& params = {});

/// The first column of the first row as an integer (or `fallback` if there is no row / NULL).
std::int64_t selectInt(sqlite3* db, std::string_view sql, std::int64_t fallback = 0);

}  // namespace sql
}  // namespace dash::log
