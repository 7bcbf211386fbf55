#include "engine/core/check.h"

#include <cstdio>
#include <cstdlib>

namespace dash {

void abortWithMessage(const char* condition, const char* file, int line,
                      const std::string& message) {
  std::fprintf(stderr, "dashbench: internal error: %s failed at %s:%d%s%s\n", condition, file,
               line, message.empty() ? "" : ": ", message.c_str());
  std::abort();
}

}  // namespace dash
