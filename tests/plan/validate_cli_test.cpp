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

}  // namespace
}  // namespace dash
