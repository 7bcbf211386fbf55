// A number too large for a double (1e400) in a scene, plan, robot model or batch spec: the JSON
// library throws out_of_range there, not parse_error. Each parser turns it into its own clean error
// naming the problem, and the command line exits 2, instead of the exception aborting the process.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>

#include "engine/core/check.h"
#include "engine/plan/plan_json.h"
#include "engine/robots/robot_model.h"
#include "engine/scene/scene_json.h"
#include "server/batch/batch_spec.h"
#include "tests/common/cli_run.h"
#include "tests/common/examples.h"
#include "tests/common/robot_library.h"
#include "tests/common/temp_dir.h"

namespace dash::test {
namespace {

constexpr const char* kOverflow = "number overflow parsing '1e400'";

/// `text` with the first number after the key `"field"` replaced by 1e400.
std::string withOverflow(const std::string& text, const std::string& field) {
  const std::size_t key = text.find("\"" + field + "\"");
  if (key == std::string::npos) throw std::runtime_error("no field " + field);
  const std::size_t start = text.find_first_of("-0123456789", key + field.size() + 2);
  const std::size_t end = text.find_first_not_of("-+.eE0123456789", start);
  return text.substr(0, start) + "1e400" + text.substr(end);
}

std::string robotModelText() { return readFile(std::string(DASHBENCH_DATA_DIR) + "/robots/ur5e.json"); }

std::string batchSpecText() {
  return R"({"name": "overflow", "time_limit": 30, "scenarios": [{"family": "sorting", "params": {"robots": 2}}],
             "planners": [{"name": "lazy-dash"}], "seeds": [1]})";
}

/// Runs `parse` and returns its InputError's message; fails the test if it throws nothing or another type.
template <class Parse>
std::string inputErrorOf(Parse parse) {
  try {
    parse();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return "";
  }
  ADD_FAILURE() << "no error";
  return "";
}

TEST(NumberOverflow, SceneIsAnInvalidJsonError) {
  const std::string text = withOverflow(readFile(exampleScenePath()), "home");
  const std::string message = inputErrorOf([&] { parseScene(text, library(), "s.json"); });
  EXPECT_NE(message.find("s.json: scene: invalid JSON"), std::string::npos) << message;
  EXPECT_NE(message.find(kOverflow), std::string::npos) << message;
}

TEST(NumberOverflow, PlanIsAnInvalidJsonError) {
  const std::string text = withOverflow(readFile(examplePlanPath()), "makespan");
  const std::string message = inputErrorOf([&] { parsePlan(text, "p.json"); });
  EXPECT_NE(message.find("p.json: plan: invalid JSON"), std::string::npos) << message;
  EXPECT_NE(message.find(kOverflow), std::string::npos) << message;
}

TEST(NumberOverflow, RobotModelIsAnInvalidJsonError) {
  const std::string text = withOverflow(robotModelText(), "a");
  const std::string message = inputErrorOf([&] { parseRobotModel(text, "r.json"); });
  EXPECT_NE(message.find("r.json: robot model: invalid JSON"), std::string::npos) << message;
  EXPECT_NE(message.find(kOverflow), std::string::npos) << message;
}

TEST(NumberOverflow, BatchSpecIsASyntaxError) {
  const std::string text = withOverflow(batchSpecText(), "time_limit");
  try {
    batch::parseBatchSpec(text, "b.json", batch::SpecOptions{.check_combinations = false});
    ADD_FAILURE() << "no error";
  } catch (const batch::SpecError& e) {
    EXPECT_EQ(e.kind(), batch::SpecErrorKind::kSyntax);
    EXPECT_NE(std::string(e.what()).find("b.json: invalid JSON"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(kOverflow), std::string::npos) << e.what();
  }
}

// The command line: exit 2 (invalid input) with the message, never an abort.
void expectExitTwo(const std::string& arguments) {
  const CliRun run = runDashbench(arguments);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(kOverflow), std::string::npos) << run.output;
}

TEST(NumberOverflow, CommandLineExitsWithTwo) {
  const TempDir dir("dashbench-overflow");
  const std::string scene = dir.write("scene.json", withOverflow(readFile(exampleScenePath()), "home"));
  const std::string plan = dir.write("plan.json", withOverflow(readFile(examplePlanPath()), "makespan"));
  const std::string spec = dir.write("spec.json", withOverflow(batchSpecText(), "time_limit"));
  expectExitTwo("check-scene '" + scene + "'");
  expectExitTwo("validate --scene '" + exampleScenePath() + "' --plan '" + plan + "'");
  expectExitTwo("batch plan '" + spec + "'");
  // The robot models come from $DASHBENCH_DATA/robots.
  std::filesystem::create_directories(dir.path() / "robots");
  dir.write("robots/ur5e.json", withOverflow(robotModelText(), "a"));
  const char* before = std::getenv("DASHBENCH_DATA");
  const std::string saved = before == nullptr ? "" : before;
  setenv("DASHBENCH_DATA", dir.path().c_str(), 1);
  expectExitTwo("fk --robot ur5e --q 0,0,0,0,0,0");
  if (before == nullptr) {
    unsetenv("DASHBENCH_DATA");
  } else {
    setenv("DASHBENCH_DATA", saved.c_str(), 1);
  }
}

}  // namespace
}  // namespace dash::test
