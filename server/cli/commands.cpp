// The table of subcommands. Each command lives in its own cmd_*.cpp file.
#include "server/cli/command.h"

namespace dash::cli {

int runServe(const std::vector<std::string>& words);
extern const char* const kServeHelp;

const std::vector<Command>& allCommands() {
  static const std::vector<Command> commands = {
      {"serve", "start the HTTP server and web dashboard", kServeHelp, runServe},
  };
  return commands;
}

}  // namespace dash::cli
