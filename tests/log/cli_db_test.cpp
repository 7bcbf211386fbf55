// `dashbench db ...` end to end, through the built binary.
#include <gtest/gtest.h>

#include <cstdio>

#include "engine/log/results_db.h"
#include "tests/common/cli_run.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

using Result = test::CliRun;

Result dashbench(const std::string& arguments) { return test::runDashbench(arguments); }

std::string quoted(const std::string& s) { return "'" + s + "'"; }

TEST(CliDb, QueryInfoExportAndMerge) {
  testing::TempDir dir;
  const std::string path = dir.file("cli.db"), other = dir.file("other.db"), out = dir.file("merged.db");
  std::string uuid;
  {
    ResultsDb db(path);
    uuid = testing::recordRun(db, testing::sampleMeta(), 5);
  }
  {
    ResultsDb db(other);
    testing::recordRun(db, testing::sampleMeta("wall", R"({"walls":2})"), 5);
  }

  Result r = dashbench("db query " + quoted(path) + " \"SELECT family, status FROM dash_runs\"");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("sorting | solved"), std::string::npos) << r.output;

  r = dashbench("db query " + quoted(path) + " \"INSERT INTO enums VALUES ('x', 1, 'y')\"");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("refused: write statement (INSERT) is not allowed; the query console is read-only"),
            std::string::npos) << r.output;

  r = dashbench("db query " + quoted(path) + " \"SELECT uuid FROM dash_runs\" --format json");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("\"uuid\": \"" + uuid + "\""), std::string::npos) << r.output;

  r = dashbench("db info " + quoted(path));
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("schema version"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("solved"), std::string::npos) << r.output;

  r = dashbench("db export " + quoted(path) + " --format csv --runs " + uuid);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.rfind("id,uuid,", 0), 0u) << r.output;
  r = dashbench("db export " + quoted(path) + " --format json --events");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("\"events\""), std::string::npos);
  EXPECT_NE(r.output.find("\"robots\": 2"), std::string::npos) << "params should come out as JSON";
  r = dashbench("db export " + quoted(path) + " --format csv --runs no-such-uuid");
  EXPECT_EQ(r.exit_code, 2);

  r = dashbench("db merge " + quoted(out) + " " + quoted(path) + " " + quoted(other));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 runs added"), std::string::npos) << r.output;
  r = dashbench("db merge " + quoted(out) + " " + quoted(path) + " " + quoted(other));
  EXPECT_NE(r.output.find("0 runs added, 0 replaced (were running), 2 already present"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("0 dispatches added, 0 replaced (were active), 0 already present"), std::string::npos)
      << r.output;

  r = dashbench("db frobnicate x");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("unknown db subcommand"), std::string::npos);
}

}  // namespace
}  // namespace dash::log
