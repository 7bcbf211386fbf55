#pragma once
// The robot models of data/robots, loaded once per test process.
#include <memory>

#include "engine/robots/robot_model.h"

namespace dash::test {

inline std::shared_ptr<const RobotLibrary> library() {
  static const auto lib = RobotLibrary::loadDefault();
  return lib;
}

}  // namespace dash::test
