// The table of subcommands. Each command lives in its own cmd_*.cpp file.
#include "server/cli/command.h"

namespace dash::cli {

int runServe(const std::vector<std::string>& words);
extern const char* const kServeHelp;
int runDb(const std::vector<std::string>& words);
extern const char* const kDbHelp;
int runCheckScene(const std::vector<std::string>& words);
extern const char* const kCheckSceneHelp;
int runScenario(const std::vector<std::string>& words);
extern const char* const kScenarioHelp;
int runValidate(const std::vector<std::string>& words);
extern const char* const kValidateHelp;
int runPlan(const std::vector<std::string>& words);
extern const char* const kPlanHelp;
int runFk(const std::vector<std::string>& words);
extern const char* const kFkHelp;
int runIk(const std::vector<std::string>& words);
extern const char* const kIkHelp;
int runTpg(const std::vector<std::string>& words);
extern const char* const kTpgHelp;
int runController(const std::vector<std::string>& words);
extern const char* const kControllerHelp;
int runBatch(const std::vector<std::string>& words);
extern const char* const kBatchHelp;
int runReport(const std::vector<std::string>& words);
extern const char* const kReportHelp;
int runRunOne(const std::vector<std::string>& words);
extern const char* const kRunOneHelp;
int runQueryWorker(const std::vector<std::string>& words);
extern const char* const kQueryWorkerHelp;

const std::vector<Command>& allCommands() {
  static const std::vector<Command> commands = {
      {"serve", "start the HTTP server and web dashboard", kServeHelp, runServe},
      {"db", "query, export, merge and inspect results databases", kDbHelp, runDb},
      {"check-scene", "check a scene file: collisions, stable resting, graspable objects", kCheckSceneHelp,
       runCheckScene},
      {"scenario", "generate a scene of a scenario family (sorting, wall, shelf-wall, stocking, lab)",
       kScenarioHelp, runScenario},
      {"plan", "plan a scene with Lazy-DaSH (or DaSH); write the plan, or print the task-level schedule",
       kPlanHelp, runPlan},
      {"validate", "check a plan file against its scene and the plan contract", kValidateHelp, runValidate},
      {"tpg", "the temporal plan graph of a plan (execution by dependencies) and its replay check", kTpgHelp,
       runTpg},
      {"fk", "forward kinematics of a robot model (flange and TCP poses)", kFkHelp, runFk},
      {"ik", "all inverse-kinematics solutions of a robot model for a TCP pose", kIkHelp, runIk},
      {"controller", "the agent next to one arm: takes dispatched plans from the server (sim or UR driver)",
       kControllerHelp, runController},
      {"batch", "experiment batches from spec files: plan, run (a process per run, or on Slurm), resume, status, cancel",
       kBatchHelp, runBatch},
      {"report", "the paper's tables from a results database: sizes, time breakdown, success rates",
       kReportHelp, runReport},
      {"run-one", "(internal) one run of a batch in its own process; started by `batch run`", kRunOneHelp,
       runRunOne},
      {"query-worker", "(internal) one query of the server's SQL console in its own process; started by `serve`",
       kQueryWorkerHelp, runQueryWorker},
  };
  return commands;
}

}  // namespace dash::cli
