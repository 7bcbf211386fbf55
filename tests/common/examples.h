#pragma once
// The format examples of docs/examples (DASHBENCH_EXAMPLES_DIR, defined by tests/CMakeLists.txt), and
// reading a file whole.
#include <fstream>
#include <sstream>
#include <string>

namespace dash::test {

inline std::string examplesDir() { return std::string(DASHBENCH_EXAMPLES_DIR) + "/"; }
inline std::string exampleScenePath() { return examplesDir() + "pick_place_scene.json"; }
inline std::string examplePlanPath() { return examplesDir() + "pick_place_plan.json"; }

/// The whole file as text; empty when it cannot be read.
inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace dash::test
