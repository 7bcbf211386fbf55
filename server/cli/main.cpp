// dashbench: the workbench's single command-line entry point.
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "engine/core/check.h"
#include "server/cli/command.h"

namespace {

void printUsage() {
  std::printf("usage: dashbench SUBCOMMAND [OPTIONS]\n\nSubcommands:\n");
  for (const auto& c : dash::cli::allCommands()) std::printf("  %-14s %s\n", c.name, c.summary);
  std::printf("\nRun 'dashbench SUBCOMMAND --help' for the options of one subcommand.\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0 ||
      std::strcmp(argv[1], "help") == 0) {
    printUsage();
    return argc < 2 ? dash::cli::kExitBadInput : dash::cli::kExitOk;
  }
  const std::string name = argv[1];
  std::vector<std::string> words(argv + 2, argv + argc);
  for (const auto& c : dash::cli::allCommands()) {
    if (name != c.name) continue;
    for (const auto& w : words) {
      if (w == "--help" || w == "-h") {
        std::fputs(c.help, stdout);
        return dash::cli::kExitOk;
      }
    }
    try {
      return c.run(words);
    } catch (const dash::InputError& e) {
      std::fprintf(stderr, "dashbench %s: error: %s\n", c.name, e.what());
      return dash::cli::kExitBadInput;
    }
  }
  std::fprintf(stderr, "dashbench: unknown subcommand '%s'\n\n", name.c_str());
  printUsage();
  return dash::cli::kExitBadInput;
}
