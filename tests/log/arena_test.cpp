// Planner Arena's loader rules, read from the schema of a results file.
#include <gtest/gtest.h>

#include "engine/log/arena_views.h"
#include "engine/log/results_db.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

std::vector<std::string> columnsOf(const ResultsDb& db, const std::string& table) {
  std::vector<std::string> out;
  for (const auto& row : db.select("SELECT name FROM pragma_table_info(?) ORDER BY cid", {table}).rows) {
    out.push_back(std::get<std::string>(row[0]));
  }
  return out;
}

class PlannerArena : public ::testing::Test {
 protected:
  void SetUp() override {
    ResultsDb db(path_);
    // Three families with different parameter names; "time" clashes with a runs attribute.
    testing::recordRun(db, testing::sampleMeta("sorting", R"({"robots":4,"objects":8})"), 5);
    testing::recordRun(db, testing::sampleMeta("sorting", R"({"robots":4,"objects":8})", "dash", 2), 5);
    testing::recordRun(db, testing::sampleMeta("sorting", R"({"robots":8,"objects":16})"), 5);
    testing::recordRun(db, testing::sampleMeta("wall", R"({"robots":8,"walls":4,"objects":40})"), 5);
    testing::recordRun(db, testing::sampleMeta("lab", R"({"containers":8,"time":3})", "dash"), 5);
    db.beginRun(testing::sampleMeta("lab", R"({"containers":8,"time":3})"));  // still running
  }

  testing::TempDir dir_;
  std::string path_ = dir_.file("arena.db");
};

TEST_F(PlannerArena, ExperimentsHaveTheTwelveColumnsFirstThenParameters) {
  const ResultsDb db(path_, OpenMode::ReadOnly);
  const auto columns = columnsOf(db, "experiments");
  const std::vector<std::string> first12 = {"id",       "name",    "totaltime", "timelimit", "memorylimit", "runcount",
                                            "version",  "hostname", "cpuinfo",  "date",      "seed",        "setup"};
  ASSERT_GE(columns.size(), 12u);
  EXPECT_EQ(std::vector<std::string>(columns.begin(), columns.begin() + 12), first12);
  const std::vector<std::string> parameters(columns.begin() + 12, columns.end());
  EXPECT_EQ(parameters, (std::vector<std::string>{"containers", "objects", "robots", "param_time", "walls"}));

  const SqlRows rows = db.select("SELECT name, version, robots, walls, containers, param_time, runcount FROM experiments ORDER BY id");
  ASSERT_EQ(rows.rows.size(), 4u);  // sorting x2 parameter sets, wall, lab
  for (const auto& row : rows.rows) {
    ASSERT_TRUE(std::holds_alternative<std::string>(row[1])) << "version must be non-null";
    EXPECT_EQ(std::get<std::string>(row[1]), "dashbench 0.1.0-test");
  }
  EXPECT_EQ(std::get<std::string>(rows.rows[0][0]), "sorting");
  EXPECT_EQ(std::get<std::int64_t>(rows.rows[0][2]), 4);
  EXPECT_TRUE(std::holds_alternative<std::monostate>(rows.rows[0][3]));  // sorting has no walls
  EXPECT_EQ(std::get<std::int64_t>(rows.rows[0][6]), 1);                  // one run per planner
  EXPECT_EQ(std::get<std::int64_t>(rows.rows[3][4]), 8);
  EXPECT_EQ(std::get<std::int64_t>(rows.rows[3][5]), 3);
}

TEST_F(PlannerArena, RunsStartWithIdExperimentidPlannerid) {
  const ResultsDb db(path_, OpenMode::ReadOnly);
  const auto columns = columnsOf(db, "runs");
  ASSERT_GE(columns.size(), 7u);
  EXPECT_EQ(std::vector<std::string>(columns.begin(), columns.begin() + 3),
            (std::vector<std::string>{"id", "experimentid", "plannerid"}));
  EXPECT_EQ(std::vector<std::string>(columns.begin() + 3, columns.end()), arenaRunAttributes());
  for (const char* attribute : {"time", "memory", "solved", "status", "time_task_query", "task_hyperarcs",
                                "motion_extended_vertices", "collision_checks_lazy", "makespan"}) {
    EXPECT_NE(std::find(columns.begin(), columns.end(), attribute), columns.end()) << attribute;
  }
  // Finished runs only; every id resolves, as Planner Arena's joins need.
  EXPECT_EQ(std::get<std::int64_t>(db.select("SELECT COUNT(*) FROM runs").rows[0][0]), 5);
  EXPECT_EQ(std::get<std::int64_t>(db.select("SELECT COUNT(*) FROM runs r JOIN experiments e ON e.id = r.experimentid "
                                             "JOIN plannerConfigs p ON p.id = r.plannerid").rows[0][0]), 5);
  EXPECT_EQ(std::get<std::int64_t>(db.select("SELECT COUNT(*) FROM runs WHERE status NOT IN "
                                             "(SELECT value FROM enums WHERE name = 'status')").rows[0][0]), 0);
  EXPECT_EQ(std::get<std::int64_t>(db.select("SELECT SUM(solved) FROM runs").rows[0][0]), 5);
}

TEST_F(PlannerArena, PlannerConfigsEnumsAndProgressExist) {
  const ResultsDb db(path_, OpenMode::ReadOnly);
  EXPECT_EQ(columnsOf(db, "plannerConfigs"), (std::vector<std::string>{"id", "name", "settings"}));
  EXPECT_EQ(columnsOf(db, "enums"), (std::vector<std::string>{"name", "value", "description"}));
  const auto progress = columnsOf(db, "progress");
  ASSERT_GE(progress.size(), 3u);
  EXPECT_EQ(progress[0], "runid");
  EXPECT_EQ(progress[1], "time");
  EXPECT_EQ(std::get<std::int64_t>(db.select("SELECT COUNT(*) FROM plannerConfigs").rows[0][0]), 2);
  const SqlRows solved = db.select("SELECT value FROM enums WHERE name = 'status' AND description = 'solved'");
  ASSERT_EQ(solved.rows.size(), 1u);
  EXPECT_GT(std::get<std::int64_t>(db.select("SELECT COUNT(*) FROM progress").rows[0][0]), 5);
}

TEST(PlannerArenaNames, ClashingParametersArePrefixed) {
  EXPECT_EQ(arenaParameterColumn("robots"), "robots");
  EXPECT_EQ(arenaParameterColumn("time"), "param_time");
  EXPECT_EQ(arenaParameterColumn("Version"), "param_Version");
  EXPECT_EQ(arenaParameterColumn("path_length"), "param_path_length");
  EXPECT_EQ(arenaParameterColumn("planner"), "param_planner");
}

}  // namespace
}  // namespace dash::log
