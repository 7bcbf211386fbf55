#pragma once
// One `dashbench SUBCOMMAND`: its name, a one-line summary for --help, its own help text, and run().
// Exit codes used across the CLI: 0 ok, 1 the check found problems, 2 bad input, 3 not solved.
#include <string>
#include <vector>

namespace dash::cli {

inline constexpr int kExitOk = 0;
inline constexpr int kExitProblems = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitNotSolved = 3;

struct Command {
  const char* name;
  const char* summary;
  const char* help;  ///< printed for `dashbench NAME --help`
  int (*run)(const std::vector<std::string>& words);
};

/// Every subcommand, in the order --help lists them (defined in commands.cpp).
const std::vector<Command>& allCommands();

}  // namespace dash::cli
