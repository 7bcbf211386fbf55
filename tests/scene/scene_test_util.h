#pragma once
// Shared helpers of the scene tests: the contract's example scene and the robot library.
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "engine/robots/robot_model.h"

namespace dash::test {

inline std::shared_ptr<const RobotLibrary> library() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib;
}

inline std::string examplePath() { return std::string(DASHBENCH_EXAMPLES_DIR) + "/pick_place_scene.json"; }

inline std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace dash::test
