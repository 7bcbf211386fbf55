// Every batch spec under experiments/ validates (parameters in the registry's ranges, combinations
// the generators accept). A spec that names a planner this build lacks ("dash" before it lands) is
// skipped with a message, never passed silently. Quick variants must finish in under a minute
// with 2 workers even if every run hits its time limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "engine/core/planner_params.h"
#include "engine/planners/planner.h"
#include "server/batch/batch_spec.h"

namespace dash::batch {
namespace {

namespace fs = std::filesystem;

const fs::path kExperiments = fs::path(DASHBENCH_SOURCE_DIR) / "experiments";

std::vector<std::string> specFiles() {
  std::vector<std::string> out;
  for (auto it = fs::recursive_directory_iterator(kExperiments); it != fs::recursive_directory_iterator(); ++it) {
    // bench/ holds the Google Benchmark programs, not batch specs.
    if (it->is_directory() && it->path().filename() == "bench") {
      it.disable_recursion_pending();
      continue;
    }
    const fs::directory_entry& entry = *it;
    if (entry.is_regular_file() && entry.path().extension() == ".json") {
      out.push_back(fs::relative(entry.path(), kExperiments).string());
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

/// The paper's figures: one full and one quick spec each.
const std::vector<std::string> kFigures = {"sorting", "wall", "shelf-wall", "stocking", "lab"};

class ExperimentSpec : public ::testing::TestWithParam<std::string> {};

TEST_P(ExperimentSpec, Validates) {
  const std::string path = (kExperiments / GetParam()).string();
  BatchSpec spec;
  ASSERT_NO_THROW(spec = loadBatchSpec(path, SpecOptions{.allow_unknown_planners = true})) << path;
  EXPECT_FALSE(spec.description.empty()) << path;
  const std::size_t runs = countRuns(spec);
  EXPECT_GT(runs, 0u);
  EXPECT_EQ(expandRuns(spec).size(), runs);

  if (GetParam().rfind("quick/", 0) == 0) {
    // Worst case: every run uses its whole limit (+5% + slack before SIGTERM, 2 s grace before SIGKILL,
    // about a second to start and generate its scene), two at a time.
    const double per_run = spec.time_limit * 1.05 + 0.5 + 2.0 + 1.0;
    const double worst = std::ceil(static_cast<double>(runs) / 2.0) * per_run;
    EXPECT_LE(worst, 60.0) << path << ": " << runs << " runs of up to " << per_run << " s with 2 workers";
    EXPECT_LE(spec.seeds.size(), 2u) << path;
  }
  if (!spec.unknown_planners.empty()) {
    std::string names;
    for (const auto& n : spec.unknown_planners) names += (names.empty() ? "" : ", ") + n;
    GTEST_SKIP() << GetParam() << " names planner(s) not in plannerNames() of this build: " << names
                 << " (the spec is otherwise valid; it runs once they exist)";
  }
}

INSTANTIATE_TEST_SUITE_P(Experiments, ExperimentSpec, ::testing::ValuesIn(specFiles()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name) {
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           }
                           return name;
                         });

TEST(Experiments, EveryFigureHasAFullAndAQuickSpecComparingLazyDashAndDash) {
  for (const std::string& figure : kFigures) {
    for (const std::string& rel : {figure + ".json", "quick/" + figure + ".json"}) {
      SCOPED_TRACE(rel);
      const fs::path path = kExperiments / rel;
      ASSERT_TRUE(fs::exists(path));
      const BatchSpec spec =
          loadBatchSpec(path.string(), SpecOptions{.allow_unknown_planners = true, .check_combinations = false});
      std::set<std::string> planners;
      for (const auto& p : spec.planners) planners.insert(p.name);
      EXPECT_EQ(planners, (std::set<std::string>{"lazy-dash", "dash"}));
      ASSERT_EQ(spec.scenarios.size(), 1u);
      EXPECT_EQ(spec.scenarios[0].family, figure);
      for (const auto& p : spec.planners) EXPECT_FALSE(p.task_only) << "figures compare full runs";
    }
  }
}

// The ablation's paper-profile row runs what `dashbench plan --profile paper` runs: every parameter
// resolves to the same value (it once switched off global sampling, budget growth and transition
// resampling, which the paper describes).
TEST(Experiments, TheAblationsPaperProfileRowIsThePlannersPaperProfile) {
  const fs::path path = kExperiments / "ablation" / "ablation.json";
  const BatchSpec spec = loadBatchSpec(path.string(), SpecOptions{.check_combinations = false});
  const auto row = std::find_if(spec.planners.begin(), spec.planners.end(),
                                [](const PlannerEntry& p) { return p.label == "paper-profile"; });
  ASSERT_NE(row, spec.planners.end());
  ASSERT_EQ(row->name, "lazy-dash");
  EXPECT_EQ(resolveParameters("lazy-dash", plannerParameterSettings(row->settings_json)),
            resolveParameters("lazy-dash", profileOverrides("lazy-dash", "paper")));
}

}  // namespace
}  // namespace dash::batch
