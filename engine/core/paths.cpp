#include "engine/core/paths.h"

#include <cstdlib>

namespace dash {

std::string dataDirectory() {
  if (const char* env = std::getenv("DASHBENCH_DATA"); env != nullptr && *env != '\0') return env;
  return DASHBENCH_DATA_DIR;
}

}  // namespace dash
