#include <gtest/gtest.h>

#include "engine/log/db_query.h"
#include "engine/log/results_db.h"
#include "engine/log/results_schema.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

class ReadOnlyQuery : public ::testing::Test {
 protected:
  void SetUp() override {
    ResultsDb db(path_);
    testing::recordRun(db, testing::sampleMeta(), 10);
    testing::recordRun(db, testing::sampleMeta("wall", R"({"walls":3})"), 10);
  }

  // Runs `sql` and expects the guard `guard` with `message` in its text.
  void expectRefused(const std::string& sql, QueryGuard guard, const std::string& message) {
    try {
      runReadOnlyQuery(path_, sql);
      ADD_FAILURE() << "not refused: " << sql;
    } catch (const QueryRefused& e) {
      EXPECT_EQ(e.guard(), guard) << sql << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << sql << ": " << e.what();
    }
  }

  std::int64_t tableCount() {
    return std::get<std::int64_t>(runReadOnlyQuery(path_, "SELECT COUNT(*) FROM sqlite_schema").rows.at(0).at(0));
  }

  testing::TempDir dir_;
  std::string path_ = dir_.file("q.db");
};

TEST_F(ReadOnlyQuery, WritesAreRefusedWithTheGuardNamed) {
  const std::int64_t tables = tableCount();
  expectRefused("INSERT INTO dash_batches (id, created) VALUES ('x', 'now')", QueryGuard::Write,
                "refused: write statement (INSERT) is not allowed; the query console is read-only");
  expectRefused("  -- comment first\n DROP TABLE dash_runs", QueryGuard::Write, "write statement (DROP");
  expectRefused("WITH x AS (SELECT 1) INSERT INTO dash_batches (id, created) SELECT 'y', 'now' FROM x",
                QueryGuard::Write, "write statement (INSERT)");
  expectRefused("UPDATE dash_runs SET status = 'solved'", QueryGuard::Write, "write statement (UPDATE)");
  expectRefused("WITH x AS (SELECT 1) UPDATE dash_runs SET status = 'x'", QueryGuard::Write, "write statement (UPDATE)");
  EXPECT_THROW(runReadOnlyQuery(path_, "WITH x AS (SELECT 1) UPDATE sqlite_master SET sql = ''"), InputError);
  expectRefused("VACUUM INTO '" + dir_.file("copy.db") + "'", QueryGuard::Write, "write statement (VACUUM)");
  expectRefused("REINDEX", QueryGuard::Write, "write statement (REINDEX)");
  expectRefused("EXPLAIN DELETE FROM dash_runs", QueryGuard::Write, "write statement (DELETE)");
  expectRefused("ATTACH DATABASE '" + dir_.file("other.db") + "' AS other", QueryGuard::Attach,
                "refused: ATTACH is not allowed");
  expectRefused("DETACH DATABASE main", QueryGuard::Attach, "refused: DETACH is not allowed");
  expectRefused("PRAGMA writable_schema = 1", QueryGuard::Pragma, "refused: PRAGMA writable_schema = 1 is not allowed");
  expectRefused("PRAGMA user_version = 9", QueryGuard::Pragma, "PRAGMA user_version = 9");
  expectRefused("PRAGMA journal_mode = DELETE", QueryGuard::Pragma, "PRAGMA journal_mode");
  expectRefused("BEGIN IMMEDIATE", QueryGuard::Transaction, "transaction control (BEGIN)");
  expectRefused("SELECT 1; DROP TABLE dash_runs", QueryGuard::OneStatement, "more than one statement");
  EXPECT_EQ(tableCount(), tables);
  EXPECT_FALSE(std::filesystem::exists(dir_.file("copy.db")));
  ResultsDb check(path_, OpenMode::ReadOnly);
  EXPECT_EQ(check.schemaVersion(), kSchemaVersion);
  EXPECT_EQ(testing::integrityCheck(path_), "ok");
}

TEST_F(ReadOnlyQuery, SelectsAndReadOnlyPragmasPass) {
  const SqlRows rows = runReadOnlyQuery(path_, "SELECT family, status FROM dash_runs ORDER BY id;  -- trailing");
  ASSERT_EQ(rows.rows.size(), 2u);
  EXPECT_EQ(rows.columns, (std::vector<std::string>{"family", "status"}));
  EXPECT_EQ(std::get<std::string>(rows.rows[1][0]), "wall");
  EXPECT_FALSE(rows.truncated);
  EXPECT_GT(runReadOnlyQuery(path_, "PRAGMA table_info(dash_runs)").rows.size(), 40u);
  EXPECT_EQ(runReadOnlyQuery(path_, "PRAGMA user_version").rows.size(), 1u);
  EXPECT_EQ(runReadOnlyQuery(path_, "SELECT name FROM pragma_table_info('runs') LIMIT 3").rows.size(), 3u);
  EXPECT_EQ(runReadOnlyQuery(path_, "SELECT * FROM experiments").rows.size(), 2u);
}

TEST_F(ReadOnlyQuery, TheRowLimitStopsTheOutput) {
  const SqlRows rows = runReadOnlyQuery(path_, "SELECT * FROM dash_events", QueryLimits{.max_rows = 5});
  EXPECT_EQ(rows.rows.size(), 5u);
  EXPECT_TRUE(rows.truncated);
  EXPECT_NE(formatRows(rows, OutputFormat::Table).find("stopped by the row limit"), std::string::npos);
}

TEST_F(ReadOnlyQuery, TheTimeLimitStopsARunawayQuery) {
  try {
    runReadOnlyQuery(path_, "WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i + 1 FROM c) SELECT COUNT(*) FROM c",
                     QueryLimits{.timeout_seconds = 0.2});
    FAIL() << "an endless query was not stopped";
  } catch (const QueryRefused& e) {
    EXPECT_EQ(e.guard(), QueryGuard::TimeLimit);
    EXPECT_NE(std::string(e.what()).find("time limit of 0.2 s"), std::string::npos) << e.what();
  }
}

TEST_F(ReadOnlyQuery, SqlErrorsAndMissingFilesAreInputErrors) {
  EXPECT_THROW(runReadOnlyQuery(path_, "SELEC 1"), InputError);
  EXPECT_THROW(runReadOnlyQuery(path_, "SELECT * FROM no_such_table"), InputError);
  EXPECT_THROW(runReadOnlyQuery(dir_.file("missing.db"), "SELECT 1"), InputError);
  EXPECT_THROW(runReadOnlyQuery(path_, "   "), InputError);
  EXPECT_FALSE(std::filesystem::exists(dir_.file("missing.db")));
}

TEST(QueryFormat, CsvQuotesAndJsonKeepsTypes) {
  SqlRows rows;
  rows.columns = {"name", "n", "x", "none"};
  rows.rows.push_back({std::string("a,\"b\"\nc"), std::int64_t{3}, 0.5, std::monostate{}});
  EXPECT_EQ(formatRows(rows, OutputFormat::Csv), "name,n,x,none\n\"a,\"\"b\"\"\nc\",3,0.5,\n");
  EXPECT_EQ(formatRows(rows, OutputFormat::Json),
            "[\n  {\n    \"n\": 3,\n    \"name\": \"a,\\\"b\\\"\\nc\",\n    \"none\": null,\n    \"x\": 0.5\n  }\n]\n");
  const std::string table = formatRows(rows, OutputFormat::Table);
  EXPECT_NE(table.find("NULL"), std::string::npos);
  EXPECT_NE(table.find("(1 row)"), std::string::npos);
  EXPECT_THROW(parseOutputFormat("xml"), InputError);
}

// Issue 24: what one query may cost.
TEST_F(ReadOnlyQuery, FunctionsThatEscapeTheLimitsAreRefused) {
  expectRefused("SELECT printf('%.*c', 400000000, 'x')", QueryGuard::Function, "printf() is not allowed");
  expectRefused("SELECT FORMAT('%d', 1)", QueryGuard::Function, "format() is not allowed");
  expectRefused("SELECT fts3_tokenizer('simple')", QueryGuard::Function, "fts3_tokenizer() is not allowed");
  // A view of the schema may use printf (dash_timeline does).
  EXPECT_NO_THROW(runReadOnlyQuery(path_, "SELECT * FROM dash_timeline LIMIT 1"));
}

TEST_F(ReadOnlyQuery, CellColumnAndByteLimits) {
  const QueryLimits limits{.max_rows = 1000, .max_cell_bytes = 1 << 20, .max_columns = 3, .max_result_bytes = 3 << 20};
  EXPECT_THROW(runReadOnlyQuery(path_, "SELECT zeroblob(2000000)", limits), InputError);
  EXPECT_THROW(runReadOnlyQuery(path_, "SELECT 1, 2, 3, 4", limits), InputError);
  const SqlRows rows = runReadOnlyQuery(
      path_, "WITH RECURSIVE c(i) AS (SELECT 1 UNION ALL SELECT i+1 FROM c LIMIT 10) SELECT hex(zeroblob(400000)) FROM c",
      limits);
  EXPECT_TRUE(rows.truncated);
  EXPECT_EQ(rows.rows.size(), 4u) << "3 MB of 800 KB cells: the fourth row crosses the budget";
}

}  // namespace
}  // namespace dash::log
