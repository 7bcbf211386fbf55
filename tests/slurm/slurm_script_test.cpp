// Job arrays without a cluster: resources from the limits, chunking, the script, the manifest.
#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <string>

#include "server/batch/batch_spec.h"
#include "server/batch/slurm_script.h"
#include "server/batch/slurm_task.h"

namespace dash::batch {
namespace {

TEST(SlurmResources, TimeAndMemoryComeFromTheLimitsWithAMargin) {
  // 300 s * 1.25 + 60 s per run, + 60 s for the task: 495 s -> 9 minutes.
  const SlurmResources one = taskResources(300, 8192, 1);
  EXPECT_EQ(one.time_minutes, 9);
  EXPECT_EQ(one.mem_mb, 9012 + 512);  // ceil(8192 * 1.1) + the task's own 512 MB
  EXPECT_EQ(one.cpus, 1);
  // Four runs one after another: 4 * 435 + 60 = 1800 s.
  EXPECT_EQ(taskResources(300, 8192, 4).time_minutes, 30);
  EXPECT_EQ(taskResources(300, 8192, 4).mem_mb, one.mem_mb);  // runs share the task one at a time
  EXPECT_EQ(taskResources(1, 0, 1).mem_mb, 0);                // no memory limit: no --mem
  EXPECT_EQ(taskResources(1, 0, 1).time_minutes, 3);
  EXPECT_THROW(taskResources(0, 100, 1), InputError);
  EXPECT_THROW(taskResources(10, 100, 0), InputError);
}

TEST(SlurmResources, SlurmTimeSyntax) {
  EXPECT_EQ(formatSlurmTime(9), "0:09:00");
  EXPECT_EQ(formatSlurmTime(125), "2:05:00");
  EXPECT_EQ(formatSlurmTime(24 * 60 + 61), "1-01:01:00");
  EXPECT_THROW(formatSlurmTime(0), InputError);
}

TEST(SlurmChunks, RunsPerTaskKeepTheArrayWithinSlurmsLimit) {
  EXPECT_EQ(runsPerTask(10, 1), 1);
  EXPECT_EQ(runsPerTask(10, 3), 3);
  EXPECT_EQ(runsPerTask(2500, 1), 3);  // 1000 tasks at most
  EXPECT_THROW(runsPerTask(10, 0), InputError);
  const auto chunks = chunkRuns(7, 3);
  ASSERT_EQ(chunks.size(), 3u);
  EXPECT_EQ(chunks[0], (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(chunks[2], (std::vector<int>{6}));
  EXPECT_TRUE(chunkRuns(0, 1).empty());
}

JobScript exampleJob() {
  JobScript job;
  job.job_name = "dashbench-sorting";
  job.tasks = 40;
  job.max_parallel = 8;
  job.resources = taskResources(300, 8192, 1);
  job.partition = "short";
  job.account = "lab42";
  job.log_dir = "/shared/results.db.slurm/b1/s1";
  job.executable = "/opt/dash bench/dashbench";
  job.manifest = "/shared/results.db.slurm/b1/s1/manifest.json";
  return job;
}

TEST(SlurmScript, ArrayResourcesAndTheTaskCommand) {
  const std::string script = formatJobScript(exampleJob());
  EXPECT_EQ(script.rfind("#!/bin/bash\n", 0), 0u);
  for (const char* line : {"#SBATCH --array=0-39%8\n", "#SBATCH --cpus-per-task=1\n", "#SBATCH --time=0:09:00\n",
                           "#SBATCH --mem=9524M\n", "#SBATCH --partition=short\n", "#SBATCH --account=lab42\n",
                           "#SBATCH --job-name=dashbench-sorting\n",
                           "#SBATCH --output=/shared/results.db.slurm/b1/s1/slurm-%A_%a.out\n"}) {
    EXPECT_NE(script.find(line), std::string::npos) << line << " missing in\n" << script;
  }
  EXPECT_NE(script.find("exec '/opt/dash bench/dashbench' batch slurm-task --manifest "
                        "'/shared/results.db.slurm/b1/s1/manifest.json' --task \"$SLURM_ARRAY_TASK_ID\"\n"),
            std::string::npos)
      << script;
}

TEST(SlurmScript, OptionalLinesAndBadValues) {
  JobScript job = exampleJob();
  job.max_parallel = 0;
  job.partition.clear();
  job.account.clear();
  job.resources.mem_mb = 0;
  const std::string script = formatJobScript(job);
  EXPECT_NE(script.find("#SBATCH --array=0-39\n"), std::string::npos);
  EXPECT_EQ(script.find("--partition"), std::string::npos);
  EXPECT_EQ(script.find("--account"), std::string::npos);
  EXPECT_EQ(script.find("--mem"), std::string::npos);

  job = exampleJob();
  job.partition = "short\n#SBATCH --nodes=100";
  EXPECT_THROW(formatJobScript(job), InputError);
  job = exampleJob();
  job.executable = "dashbench";  // must be absolute: the nodes run it from the job's directory
  EXPECT_THROW(formatJobScript(job), InputError);
}

TEST(SlurmScript, ShellQuoting) {
  EXPECT_EQ(shellQuote("a b"), "'a b'");
  EXPECT_EQ(shellQuote("it's"), "'it'\\''s'");
}

const char* const kSpec = R"({
  "name": "tiny", "time_limit": 20, "memory_limit": 2048,
  "scenarios": [{"family": "sorting", "params": {"robots": 2, "objects": [2, 4]}}],
  "planners": [{"name": "lazy-dash", "label": "lazy-dash"},
               {"name": "lazy-dash", "settings": {"task_only": true}, "label": "lazy-task"}],
  "seeds": [1, 2]
})";

TEST(SlurmManifest, RoundTripsTheRunsOfEachTask) {
  const BatchSpec spec = parseBatchSpec(kSpec, "tiny.json", {.check_combinations = false});
  const std::vector<RunSpec> runs = expandRuns(spec);
  ASSERT_EQ(runs.size(), 8u);
  SlurmManifest m{.batch_id = "tiny-1", .name = "tiny", .submission = 2, .shard_dir = "/shared/x/s2"};
  m.tasks = {{runs[0], runs[1], runs[2]}, {runs[7]}};
  std::string dir = (std::filesystem::temp_directory_path() / "dash_slurm_XXXXXX").string();
  ASSERT_NE(mkdtemp(dir.data()), nullptr);
  const std::string path = dir + "/manifest.json";
  writeManifest(path, m);
  const SlurmManifest back = readManifest(path);
  std::filesystem::remove_all(dir);
  EXPECT_EQ(back.batch_id, "tiny-1");
  EXPECT_EQ(back.name, "tiny");
  EXPECT_EQ(back.submission, 2);
  EXPECT_EQ(back.shard_dir, "/shared/x/s2");
  ASSERT_EQ(back.tasks.size(), 2u);
  ASSERT_EQ(back.tasks[0].size(), 3u);
  EXPECT_EQ(back.tasks[0][2].key, runs[2].key);
  EXPECT_EQ(back.tasks[1][0].toJson(), runs[7].toJson());
  EXPECT_THROW(readManifest(dir + "/missing.json"), InputError);
  EXPECT_EQ(shardPath("/s", 3), "/s/task-3.db");
  EXPECT_EQ(taskStatePath("/s", 3), "/s/task-3.state");
}

TEST(SlurmManifest, ASingleRunSpecExpandsToThatRun) {
  // An array task runs each run as a one-run batch: same key, settings and limits.
  const BatchSpec spec = parseBatchSpec(kSpec, "tiny.json", {.check_combinations = false});
  for (const RunSpec& run : expandRuns(spec)) {
    const std::vector<RunSpec> one = expandRuns(singleRunSpec(run, spec.name));
    ASSERT_EQ(one.size(), 1u);
    RunSpec expected = run;
    expected.ordinal = 0;
    EXPECT_EQ(one[0].toJson(), expected.toJson());
  }
}

}  // namespace
}  // namespace dash::batch
