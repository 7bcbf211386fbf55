// Slurm's output as the backend reads it, and the command runner (no cluster needed).
#include <gtest/gtest.h>

#include "engine/core/check.h"
#include "server/batch/slurm_client.h"

namespace dash::batch {
namespace {

TEST(SlurmStates, SlurmNamesMapToTheWorkbenchsStates) {
  EXPECT_EQ(parseSlurmState("PENDING"), SlurmState::kPending);
  EXPECT_EQ(parseSlurmState("REQUEUED"), SlurmState::kPending);
  EXPECT_EQ(parseSlurmState("RUNNING"), SlurmState::kRunning);
  EXPECT_EQ(parseSlurmState("COMPLETING"), SlurmState::kRunning);
  EXPECT_EQ(parseSlurmState("COMPLETED"), SlurmState::kCompleted);
  EXPECT_EQ(parseSlurmState("FAILED"), SlurmState::kFailed);
  EXPECT_EQ(parseSlurmState("OUT_OF_MEMORY"), SlurmState::kFailed);
  EXPECT_EQ(parseSlurmState("NODE_FAIL"), SlurmState::kFailed);
  EXPECT_EQ(parseSlurmState("TIMEOUT"), SlurmState::kTimeout);
  EXPECT_EQ(parseSlurmState("CANCELLED by 1000"), SlurmState::kCancelled);
  EXPECT_EQ(parseSlurmState("SOMETHING_NEW"), SlurmState::kUnknown);
  for (SlurmState s : {SlurmState::kPending, SlurmState::kRunning, SlurmState::kCompleted, SlurmState::kFailed,
                       SlurmState::kTimeout, SlurmState::kCancelled}) {
    EXPECT_EQ(slurmStateFromName(toString(s)), s);
  }
  EXPECT_FALSE(isFinal(SlurmState::kPending));
  EXPECT_FALSE(isFinal(SlurmState::kRunning));
  EXPECT_FALSE(isFinal(SlurmState::kUnknown));
  EXPECT_TRUE(isFinal(SlurmState::kTimeout));
}

TEST(SlurmOutput, SbatchJobId) {
  EXPECT_EQ(parseSbatchJobId("1234\n"), "1234");
  EXPECT_EQ(parseSbatchJobId("1234;cluster-a\n"), "1234");
  EXPECT_EQ(parseSbatchJobId("sbatch: warning: something\n77\n"), "77");
  EXPECT_THROW(parseSbatchJobId("sbatch: error: Batch job submission failed\n"), InputError);
}

TEST(SlurmOutput, ArrayStatesOfOneJob) {
  const std::string squeue =
      "12_0|COMPLETED\n12_1|RUNNING\n12_[2-5%2]|PENDING\n13_0|FAILED\n12_3|PENDING\n12_4.batch|COMPLETED\n";
  const auto states = parseArrayStates(squeue, "12");
  ASSERT_EQ(states.size(), 3u);
  EXPECT_EQ(states.at(0), SlurmState::kCompleted);
  EXPECT_EQ(states.at(1), SlurmState::kRunning);
  EXPECT_EQ(states.at(3), SlurmState::kPending);
  // sacct -P -X lines have more columns; the state is the second.
  const auto sacct = parseArrayStates("12_7|TIMEOUT|0:15\n12_8|CANCELLED by 0|0:0\n", "12");
  EXPECT_EQ(sacct.at(7), SlurmState::kTimeout);
  EXPECT_EQ(sacct.at(8), SlurmState::kCancelled);
  EXPECT_TRUE(parseArrayStates("", "12").empty());
}

TEST(SlurmCommands, RunsACommandAndCapturesItsOutput) {
  const CommandResult ok = runCommand({"sh", "-c", "echo out; echo err >&2; exit 3"});
  EXPECT_EQ(ok.exit_code, 3);
  EXPECT_EQ(ok.out, "out\n");
  EXPECT_EQ(ok.err, "err\n");
  const CommandResult missing = runCommand({"dashbench-no-such-command"});
  EXPECT_EQ(missing.exit_code, -1);
  EXPECT_FALSE(missing.err.empty());
  const CommandResult slow = runCommand({"sleep", "5"}, 0.2);
  EXPECT_EQ(slow.exit_code, 128 + 9);
  EXPECT_TRUE(onPath("sh"));
  EXPECT_FALSE(onPath("dashbench-no-such-command"));
}

}  // namespace
}  // namespace dash::batch
