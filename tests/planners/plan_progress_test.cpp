// Progress on the command line: ProgressSink's line carries conflict resolution's steps scheduled of
// the plan's while the scheduler reports them, its ticker prints again when nothing happens, and
// `dashbench plan` prints both, and the peak memory at the end; `dashbench plan` checks the scene
// first and names its problem instead of planning it to "infeasible".
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <thread>

#include "engine/planners/progress_sink.h"
#include "tests/common/cli_run.h"
#include "tests/common/temp_dir.h"

namespace dash {
namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::size_t lineCount(const std::string& text) {
  std::size_t n = 0;
  for (char c : text) n += c == '\n';
  return n;
}

log::Event progressEvent(std::int64_t done, std::int64_t total, std::string current) {
  return log::Event{1.0, 2, log::ProgressEvent{log::Phase::ConflictResolution, done, total, 2.5, std::move(current)}};
}

TEST(ProgressSink, TheLineCarriesTheStepsWhileTheSchedulerWorks) {
  test::TempDir dir;
  const std::string path = dir.file("progress.txt");
  std::FILE* out = std::fopen(path.c_str(), "w");
  ASSERT_NE(out, nullptr);
  {
    ProgressSink sink(out, false, 1e9);  // no line from the pace: only the first, flushes and ends
    sink.onEvent(log::Event{0.5, 2, log::PhaseEvent{log::Phase::ConflictResolution, log::PhaseBoundary::Start, 0.0}});
    sink.onEvent(progressEvent(3, 5, "ur5e_0, ur5e_1"));
    sink.flush();
    sink.onEvent(progressEvent(5, 5, ""));  // the build ended: its last figures at once
    sink.flush();                           // and then no more
  }
  std::fclose(out);
  const std::string text = readFile(path);
  ASSERT_EQ(lineCount(text), 4u) << text;
  std::istringstream lines(text);
  std::string first, second, third, fourth;
  std::getline(lines, first);
  std::getline(lines, second);
  std::getline(lines, third);
  std::getline(lines, fourth);
  EXPECT_NE(first.find("conflict_resolution"), std::string::npos) << first;
  EXPECT_EQ(first.find("steps"), std::string::npos) << first;  // before the first progress event
  EXPECT_NE(second.find("steps 3/5 (ur5e_0, ur5e_1) 2.5 steps/s"), std::string::npos) << second;
  EXPECT_NE(third.find("steps 5/5 2.5 steps/s"), std::string::npos) << third;
  EXPECT_EQ(fourth.find("steps"), std::string::npos) << fourth;
  EXPECT_EQ(ProgressSink::formatWork(log::ProgressEvent{log::Phase::ConflictResolution, 37, 146, 4.25, "ur5e_3"}),
            "steps 37/146 (ur5e_3) 4.2 steps/s");
}

TEST(ProgressSink, TheTickerPrintsWhenNoEventComes) {
  test::TempDir dir;
  const std::string path = dir.file("ticker.txt");
  std::FILE* out = std::fopen(path.c_str(), "w");
  ASSERT_NE(out, nullptr);
  {
    ProgressSink sink(out);
    sink.onEvent(progressEvent(7, 146, "ur5e_3, ur5e_7"));  // one event, then a long step
    sink.startTicker(0.05);
    // Wait (no timing asserted) until the ticker printed the same state again.
    for (int i = 0; i < 400 && lineCount(readFile(path)) < 3; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(25));
    sink.stopTicker();
  }
  std::fclose(out);
  const std::string text = readFile(path);
  ASSERT_GE(lineCount(text), 3u) << text;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);)
    EXPECT_NE(line.find("steps 7/146 (ur5e_3, ur5e_7)"), std::string::npos) << line;
}

TEST(ProgressSink, ALayerStillBeingBuiltReadsBuildingNotZero) {
  test::TempDir dir;
  const std::string path = dir.file("progress.txt");
  std::FILE* out = std::fopen(path.c_str(), "w");
  ASSERT_NE(out, nullptr);
  {
    ProgressSink sink(out, false, 1e9);
    // DaSH's motion construction: a phase start, then nothing for H_M until the hypergraph is whole.
    sink.onEvent(log::Event{0.1, 0, log::PhaseEvent{log::Phase::MotionConstruction, log::PhaseBoundary::Start, 0.0}});
    sink.flush();
  }
  std::fclose(out);
  const std::string text = readFile(path);
  EXPECT_NE(text.find("motion_construction 0."), std::string::npos) << text;  // the time in the phase
  EXPECT_NE(text.find("H_M building"), std::string::npos) << text;
  EXPECT_EQ(text.find("H_M 0/0"), std::string::npos) << text;
  EXPECT_NE(text.find("H_T 0/0"), std::string::npos) << text;  // not being built now: its count
  EXPECT_EQ(ProgressSink::formatLayer("H_M", 0, 0, true), "H_M building");
  EXPECT_EQ(ProgressSink::formatLayer("H_M", 12, 40, true), "H_M 12/40");
}

TEST(PlanCli, PrintsConflictResolutionProgressAndThePeakMemory) {
  test::TempDir dir;
  const std::string scene = dir.file("s.json");
  const test::CliRun gen = test::runDashbench("scenario sorting --seed 1 robots=2 objects=2 -o '" + scene + "'");
  ASSERT_EQ(gen.exit_code, 0) << gen.output;
  // --progress-every 0: a line per event, so that even a fast build's progress shows (no timing).
  const test::CliRun run =
      test::runDashbench("plan --scene '" + scene + "' --seed 1 --time-limit 120 --progress-every 0");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::regex steps(R"(conflict_resolution\s.*  steps (\d+)/(\d+)( \(([^)]*)\))? [0-9.]+ steps/s)");
  long total = -1;
  bool started = false, ended = false, robots = false;
  std::istringstream lines(run.output);
  for (std::string line; std::getline(lines, line);) {
    std::smatch m;
    if (!std::regex_search(line, m, steps)) continue;
    const long done = std::stol(m[1]);
    const long of = std::stol(m[2]);
    if (total < 0) total = of;
    EXPECT_EQ(of, total) << line;
    EXPECT_LE(done, of) << line;
    started = started || done == 0;
    ended = ended || (done == of && !m[3].matched);
    robots = robots || m[4].str().find("ur5e_") != std::string::npos;
  }
  EXPECT_GT(total, 0) << run.output;
  EXPECT_TRUE(started) << run.output;
  EXPECT_TRUE(ended) << run.output;
  EXPECT_TRUE(robots) << run.output;
  EXPECT_TRUE(std::regex_search(run.output, std::regex(R"(peak memory: [0-9]+\.[0-9] MB)"))) << run.output;
}

TEST(PlanCli, NamesTheSceneProblemOfAnObjectBelowTheTableInsteadOfPlanning) {
  test::TempDir dir;
  const std::string scene = dir.file("s.json");
  const test::CliRun gen = test::runDashbench("scenario sorting --seed 1 robots=2 objects=2 -o '" + scene + "'");
  ASSERT_EQ(gen.exit_code, 0) << gen.output;
  nlohmann::json j = nlohmann::json::parse(readFile(scene));
  auto& object = j["objects"][0];
  object["start"]["p"][2] = object["start"]["p"][2].get<double>() - 0.5;  // 0.5 m below the table
  const std::string sunk = dir.file("sunk.json");
  std::ofstream(sunk) << j.dump(2);
  const std::string id = object["id"].get<std::string>();
  const test::CliRun run = test::runDashbench("plan --scene '" + sunk + "' --seed 1 --time-limit 60");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("object " + id + " does not rest on a surface"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("nothing planned"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("infeasible"), std::string::npos) << run.output;
}

TEST(PlanCli, RejectsANegativeProgressPeriod) {
  const test::CliRun run = test::runDashbench("plan --scene /nonexistent --progress-every=-1");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("progress-every"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace dash
