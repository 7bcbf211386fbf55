// `dashbench validate`: exit codes 0 (valid), 1 (problems), 2 (bad input), and its output.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "plan_test_util.h"
#include "tests/common/cli_run.h"

namespace dash {
namespace {

using test::CliRun;

CliRun runValidate(const std::string& arguments) { return test::runDashbench("validate " + arguments); }

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

const std::string kScene = "--scene " + test::exampleScenePath();

TEST(ValidateCli, ExamplePlanIsValid) {
  const CliRun run = runValidate(kScene + " --plan " + test::examplePlanPath());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("valid"), std::string::npos) << run.output;
}

TEST(ValidateCli, ProblemsExitWithOne) {
  Plan plan = test::examplePlan();
  plan.events[1].t = 2.18;  // release in mid-air
  const std::string path = writeTemp("validate_cli_midair.json", planToJson(plan));
  const CliRun run = runValidate(kScene + " --plan " + path);
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("release_unstable"), std::string::npos) << run.output;

  const CliRun json = runValidate(kScene + " --plan " + path + " --json");
  EXPECT_EQ(json.exit_code, 1) << json.output;
  EXPECT_NE(json.output.find("\"valid\": false"), std::string::npos) << json.output;
  EXPECT_NE(json.output.find("\"kind\": \"release_unstable\""), std::string::npos) << json.output;
}

TEST(ValidateCli, BadInputExitsWithTwo) {
  const std::string broken = writeTemp("validate_cli_broken.json", "{\"format\": \"dashbench.plan/1\"}");
  const CliRun run = runValidate(kScene + " --plan " + broken);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("scene: missing field"), std::string::npos) << run.output;
  EXPECT_EQ(runValidate(kScene).exit_code, 2);
  EXPECT_EQ(runValidate(kScene + " --plan /nonexistent/plan.json").exit_code, 2);
}

// The example plan's closest pair is the arm's base and the table it stands on, 5 mm apart all along.
TEST(ValidateCli, PrintsTheSmallestClearance) {
  const CliRun run = runValidate(kScene + " --plan " + test::examplePlanPath());
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("smallest clearance: 5.0000 mm between ur5e_0.base and table at t=0 (required 0 mm)"),
            std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("pair ur5e_0.base"), std::string::npos) << run.output;  // per-pair minima: --verbose

  const CliRun json = runValidate(kScene + " --plan " + test::examplePlanPath() + " --json");
  EXPECT_EQ(json.exit_code, 0) << json.output;
  EXPECT_NE(json.output.find("\"closest\""), std::string::npos) << json.output;
  EXPECT_NE(json.output.find("\"a\": \"ur5e_0.base\""), std::string::npos) << json.output;
}

TEST(ValidateCli, ALargerClearanceRejectsWhatZeroPasses) {
  const std::string plan = " --plan " + test::examplePlanPath();
  const CliRun at_5mm = runValidate(kScene + plan + " --clearance 0.005");
  EXPECT_EQ(at_5mm.exit_code, 0) << at_5mm.output;
  EXPECT_NE(at_5mm.output.find("(required 5 mm)"), std::string::npos) << at_5mm.output;

  const CliRun at_10mm = runValidate(kScene + plan + " --clearance 0.01");
  EXPECT_EQ(at_10mm.exit_code, 1) << at_10mm.output;
  EXPECT_NE(at_10mm.output.find("robot_obstacle_collision"), std::string::npos) << at_10mm.output;
  EXPECT_NE(at_10mm.output.find("robot ur5e_0 body base comes within 5 mm of obstacle table"), std::string::npos)
      << at_10mm.output;
  EXPECT_NE(at_10mm.output.find("clearance 10 mm"), std::string::npos) << at_10mm.output;
  EXPECT_NE(at_10mm.output.find("(required 10 mm)"), std::string::npos) << at_10mm.output;

  EXPECT_EQ(runValidate(kScene + plan + " --clearance -0.001").exit_code, 2);
}

TEST(ValidateCli, VerbosePrintsEveryPairClosestFirst) {
  const CliRun run = runValidate(kScene + " --plan " + test::examplePlanPath() + " --verbose");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  const std::size_t held = run.output.find("pair obj_0 (held by ur5e_0) - table: 0.1000 mm at t=1.39 (contact allowed)");
  const std::size_t base = run.output.find("pair ur5e_0.base - table: 5.0000 mm at t=0\n");
  const std::size_t summary = run.output.find("smallest clearance: 5.0000 mm");
  ASSERT_NE(held, std::string::npos) << run.output;
  ASSERT_NE(base, std::string::npos) << run.output;
  ASSERT_NE(summary, std::string::npos) << run.output;
  EXPECT_LT(held, base) << run.output;  // 0.1 mm (its lowest face's tolerance) before 5 mm: contact meant
  EXPECT_LT(base, summary) << run.output;
}

}  // namespace
}  // namespace dash
