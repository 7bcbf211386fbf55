// `dashbench scenario`: output to stdout or a file (-o / --out), --png, --list, and exit code 2 with a
// message naming the key and its range on bad input.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "engine/scene/scene_json.h"
#include "scenario_test_util.h"
#include "tests/common/cli_run.h"
#include "tests/common/examples.h"

namespace dash {
namespace {

using RunResult = test::CliRun;
using test::readFile;

RunResult runCli(const std::string& arguments) { return test::runDashbench("scenario " + arguments); }

class CliScenario : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("dashbench_scenario_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::filesystem::path dir_;
};

TEST_F(CliScenario, StdoutShortAndLongOutputAgree) {
  const RunResult out = runCli("sorting --seed 3 robots=4 objects=8");
  ASSERT_EQ(out.exit_code, 0) << out.output;
  const std::string expected = sceneToJson(test::generate("sorting", {{"robots", "4"}, {"objects", "8"}}, 3).scene);
  EXPECT_EQ(out.output, expected);
  const auto a = dir_ / "a.json";
  const auto b = dir_ / "b.json";
  ASSERT_EQ(runCli("sorting --seed 3 robots=4 objects=8 -o " + a.string()).exit_code, 0);
  ASSERT_EQ(runCli("sorting robots=4 --out " + b.string() + " objects=8 --seed=3").exit_code, 0);
  EXPECT_EQ(readFile(a.string()), expected);
  EXPECT_EQ(readFile(b.string()), expected);
}

TEST_F(CliScenario, WritesAPicture) {
  const auto png = dir_ / "s.png";
  const RunResult r = runCli("lab --seed 2 containers=3 -o " + (dir_ / "s.json").string() + " --png " + png.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(readFile(png.string()).substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
}

TEST_F(CliScenario, ListNamesEveryFamily) {
  const RunResult r = runCli("--list");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const auto& f : scenarioFamilies()) EXPECT_NE(r.output.find(f.name + ": "), std::string::npos) << f.name;
  EXPECT_NE(r.output.find("robots=4  (2..64)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("walls=1  (1..31)"), std::string::npos) << r.output;
}

TEST_F(CliScenario, BadInputExitsTwoNamingTheProblem) {
  struct Case {
    std::string args;
    std::vector<std::string> mentions;
  };
  const std::vector<Case> cases = {
      {"sortingg --seed 1", {"unknown scenario family 'sortingg'", "stocking"}},
      {"sorting --seed 1 arms=3", {"unknown parameter 'arms'", "robots (2..64)"}},
      {"sorting --seed 1 robots=70", {"robots", "out of range", "2..64"}},
      {"stocking layers=4", {"layers", "2..3"}},
      {"shelf-wall robots=3", {"robots", "even"}},
      {"lab containers=many", {"containers", "not an integer", "2..24"}},
      {"wall robots=5 walls=6", {"walls=6 needs robots >= 7"}},
      {"wall walls=32", {"walls", "1..31"}},
      {"sorting --seed -1", {"--seed"}},
      {"sorting --speed 3", {"unknown option --speed"}},
      {"", {"expected a scenario family"}},
  };
  for (const Case& c : cases) {
    const RunResult r = runCli(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.output;
    for (const std::string& m : c.mentions) EXPECT_NE(r.output.find(m), std::string::npos) << c.args << "\n" << r.output;
  }
}

}  // namespace
}  // namespace dash
