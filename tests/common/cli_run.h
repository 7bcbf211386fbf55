#pragma once
// Running the built `dashbench` binary from a test (DASHBENCH_BINARY, defined by tests/CMakeLists.txt).
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace dash::test {

struct CliRun {
  int exit_code = -1;  ///< -1: the process did not exit normally
  std::string output;  ///< stdout, and stderr too unless dropped
};

enum class Stderr { kCapture, kDrop };

/// `dashbench ARGUMENTS` through the shell; `arguments` is pasted as is (quote paths yourself).
inline CliRun runDashbench(const std::string& arguments, Stderr err = Stderr::kCapture) {
  const std::string command =
      std::string(DASHBENCH_BINARY) + " " + arguments + (err == Stderr::kCapture ? " 2>&1" : " 2>/dev/null");
  CliRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) run.output.append(buffer, n);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

}  // namespace dash::test
