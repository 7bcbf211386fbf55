// Batch spec parsing: the grid, its expansion and stable run keys, and one test per error kind.
#include <gtest/gtest.h>

#include <limits>
#include <regex>
#include <set>
#include <string>

#include "server/batch/batch_spec.h"

namespace dash::batch {
namespace {

// Combination probing generates scenes; most tests here do not need it.
const SpecOptions kFast{.check_combinations = false};

std::string validSpec() {
  return R"({
    "name": "tiny",
    "description": "two sizes of sorting",
    "time_limit": 5,
    "memory_limit": 1024,
    "scenarios": [{"family": "sorting", "params": {"robots": 4, "objects": [4, 8]}}],
    "planners": [{"name": "lazy-dash", "settings": {"task_only": true}, "label": "lazy-task"},
                 {"name": "lazy-dash"}],
    "seeds": {"from": 3, "count": 2}
  })";
}

/// Parses `text` expecting a SpecError of `kind`; returns its message.
std::string expectError(const std::string& text, SpecErrorKind kind, const SpecOptions& options = kFast) {
  try {
    parseBatchSpec(text, "spec.json", options);
  } catch (const SpecError& e) {
    EXPECT_EQ(toString(e.kind()), std::string(toString(kind))) << e.what();
    EXPECT_EQ(std::string(e.what()).rfind("spec.json: ", 0), 0u) << e.what();
    return e.what();
  }
  ADD_FAILURE() << "no error for: " << text;
  return "";
}

/// validSpec() with `from` replaced by `to` (which must occur).
std::string edit(const std::string& from, const std::string& to) {
  std::string s = validSpec();
  const auto at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(BatchSpec, ParsesTheGridAndFillsDefaults) {
  const BatchSpec spec = parseBatchSpec(validSpec(), "spec.json", kFast);
  EXPECT_EQ(spec.name, "tiny");
  EXPECT_EQ(spec.description, "two sizes of sorting");
  EXPECT_DOUBLE_EQ(spec.time_limit, 5.0);
  EXPECT_DOUBLE_EQ(spec.memory_limit_mb, 1024.0);
  ASSERT_EQ(spec.scenarios.size(), 1u);
  ASSERT_EQ(spec.scenarios[0].params.size(), 2u);
  EXPECT_EQ(spec.scenarios[0].params[0].first, "robots");
  EXPECT_EQ(spec.scenarios[0].params[0].second, std::vector<int>({4}));
  EXPECT_EQ(spec.scenarios[0].params[1].second, std::vector<int>({4, 8}));
  EXPECT_EQ(spec.seeds, std::vector<std::uint64_t>({3, 4}));
  ASSERT_EQ(spec.planners.size(), 2u);
  EXPECT_EQ(spec.planners[0].label, "lazy-task");
  EXPECT_TRUE(spec.planners[0].task_only);
  EXPECT_EQ(spec.planners[0].settings_json, R"({"task_only":true})");
  EXPECT_EQ(spec.planners[1].label, "lazy-dash");
  EXPECT_EQ(spec.planners[1].settings_json, "{}");

  // Parameters left out take the family's default; the limits have defaults too.
  const BatchSpec defaults = parseBatchSpec(
      R"({"name":"d","scenarios":[{"family":"wall"}],"planners":[{"name":"lazy-dash"}],"seeds":[1]})", "", kFast);
  ASSERT_EQ(defaults.scenarios[0].params.size(), 3u);
  EXPECT_EQ(defaults.scenarios[0].params[2].first, "walls");
  EXPECT_EQ(defaults.scenarios[0].params[2].second.size(), 1u);
  EXPECT_GT(defaults.time_limit, 0.0);
}

TEST(BatchSpec, ExpandsToStableKeysWithPlannersSideBySide) {
  const BatchSpec spec = parseBatchSpec(validSpec(), "spec.json", kFast);
  const std::vector<RunSpec> runs = expandRuns(spec);
  ASSERT_EQ(runs.size(), 8u);  // 2 object counts x 2 seeds x 2 planners
  EXPECT_EQ(countRuns(spec), 8u);
  EXPECT_EQ(runs[0].key, "sorting/robots=4,objects=4/seed=3/lazy-task");
  EXPECT_EQ(runs[1].key, "sorting/robots=4,objects=4/seed=3/lazy-dash");
  EXPECT_EQ(runs[2].key, "sorting/robots=4,objects=4/seed=4/lazy-task");
  EXPECT_EQ(runs[7].key, "sorting/robots=4,objects=8/seed=4/lazy-dash");
  std::set<std::string> keys;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].ordinal, static_cast<int>(i));
    EXPECT_DOUBLE_EQ(runs[i].time_limit, 5.0);
    EXPECT_DOUBLE_EQ(runs[i].memory_limit_mb, 1024.0);
    keys.insert(runs[i].key);
  }
  EXPECT_EQ(keys.size(), runs.size());
  EXPECT_EQ(runs[0].paramsJson(), R"({"robots":4,"objects":4})");
  EXPECT_EQ(runs[0].paramsText(), "robots=4 objects=4");
  // The same spec always expands to the same keys (what resume relies on).
  const std::vector<RunSpec> again = expandRuns(parseBatchSpec(validSpec(), "spec.json", kFast));
  for (std::size_t i = 0; i < runs.size(); ++i) EXPECT_EQ(again[i].key, runs[i].key);

  const std::string listing = formatRunList(spec, runs);
  EXPECT_NE(listing.find("batch tiny: 8 runs"), std::string::npos) << listing;
  EXPECT_NE(listing.find("sorting/robots=4,objects=8/seed=4/lazy-dash"), std::string::npos);
}

TEST(BatchSpec, TheRunListSaysOneRunAndAShortDurationInMinutesAndSeconds) {
  // One run of 5 s: "1 run" and a duration in seconds, not "1 runs" and "at most 0.0 h".
  const std::string text = R"({"name": "tiny", "time_limit": 5, "memory_limit": 1024,
    "scenarios": [{"family": "sorting", "params": {"robots": 4, "objects": 4}}],
    "planners": [{"name": "lazy-dash"}], "seeds": [1]})";
  const BatchSpec spec = parseBatchSpec(text, "spec.json", kFast);
  const std::vector<RunSpec> runs = expandRuns(spec);
  ASSERT_EQ(runs.size(), 1u);
  const std::string listing = formatRunList(spec, runs);
  EXPECT_NE(listing.find("batch tiny: 1 run ("), std::string::npos) << listing;
  EXPECT_EQ(listing.find(" h "), std::string::npos) << listing;
  EXPECT_TRUE(std::regex_search(listing, std::regex(R"(at most \d+s \(every run)"))) << listing;
}

TEST(BatchSpec, RunSpecRoundTripsThroughJson) {
  const RunSpec run = expandRuns(parseBatchSpec(validSpec(), "", kFast))[0];
  const RunSpec back = RunSpec::fromJson(run.toJson());
  EXPECT_EQ(back.key, run.key);
  EXPECT_EQ(back.family, run.family);
  EXPECT_EQ(back.params, run.params);
  EXPECT_EQ(back.seed, run.seed);
  EXPECT_EQ(back.planner, run.planner);
  EXPECT_EQ(back.label, run.label);
  EXPECT_EQ(back.settings_json, run.settings_json);
  EXPECT_EQ(back.task_only, run.task_only);
  EXPECT_DOUBLE_EQ(back.time_limit, run.time_limit);
  EXPECT_DOUBLE_EQ(back.memory_limit_mb, run.memory_limit_mb);
  EXPECT_THROW(RunSpec::fromJson("{}"), InputError);
}

TEST(BatchSpecErrors, Syntax) {
  expectError("{ not json", SpecErrorKind::kSyntax);
  expectError("[1, 2]", SpecErrorKind::kSyntax);
  const std::string msg = expectError(edit(R"("time_limit": 5)", R"("time_limit": "5")"), SpecErrorKind::kSyntax);
  EXPECT_NE(msg.find("time_limit"), std::string::npos) << msg;
  expectError(edit(R"("objects": [4, 8])", R"("objects": [4, 8.5])"), SpecErrorKind::kSyntax);
  expectError(edit(R"({"task_only": true})", R"({"task_only": 1})"), SpecErrorKind::kSyntax);
}

TEST(BatchSpecErrors, UnknownKeys) {
  std::string msg =
      expectError(edit(R"("name": "tiny")", R"("name": "tiny", "workers": 4)"), SpecErrorKind::kUnknownKey);
  EXPECT_NE(msg.find("workers"), std::string::npos) << msg;
  msg = expectError(edit(R"("family": "sorting")", R"("family": "sorting", "robot": 4)"), SpecErrorKind::kUnknownKey);
  EXPECT_NE(msg.find("scenarios[0].robot"), std::string::npos) << msg;
  msg = expectError(edit(R"("robots": 4)", R"("robots": 4, "walls": 2)"), SpecErrorKind::kUnknownKey);
  EXPECT_NE(msg.find("scenarios[0].params.walls"), std::string::npos) << msg;
  msg = expectError(edit(R"({"task_only": true})", R"({"task_only": true, "speed": 2})"), SpecErrorKind::kUnknownKey);
  EXPECT_NE(msg.find("planners[0].settings.speed"), std::string::npos) << msg;
  msg = expectError(edit(R"({"task_only": true})", R"({"seed": 2})"), SpecErrorKind::kUnknownKey);
  EXPECT_NE(msg.find("seeds"), std::string::npos) << msg;
  expectError(edit(R"({"from": 3, "count": 2})", R"({"from": 3, "count": 2, "step": 2})"), SpecErrorKind::kUnknownKey);
}

// A planner's settings also take its named parameters (engine/core/planner_params.h), checked.
TEST(BatchSpecErrors, NamedPlannerParameters) {
  const BatchSpec spec =
      parseBatchSpec(edit(R"({"task_only": true})", R"({"task_only": true, "schedule_memo": false, "motion_budget": 2})"));
  EXPECT_EQ(plannerParameterSettings(spec.planners[0].settings_json).at("schedule_memo"), "false");
  std::string msg =
      expectError(edit(R"({"task_only": true})", R"({"straight_first": "yes"})"), SpecErrorKind::kBadValue);
  EXPECT_NE(msg.find("planners[0].settings.straight_first"), std::string::npos) << msg;
  msg = expectError(edit(R"({"task_only": true})", R"({"motion_budget": 0})"), SpecErrorKind::kBadValue);
  EXPECT_NE(msg.find("motion_budget"), std::string::npos) << msg;
}

// A planner's "profile" (--profile in a spec): the profile's parameter values under the settings given
// (which win), and "profile" recorded in the settings (so in each run's results row), not a parameter.
TEST(BatchSpec, APlannerProfileExpandsIntoItsSettingsAndIsRecorded) {
  const BatchSpec spec = parseBatchSpec(
      edit(R"({"name": "lazy-dash"})",
           R"({"name": "dash", "profile": "paper", "settings": {"validator_rechecks": 2}, "label": "dash-paper"})"),
      "spec.json", kFast);
  const std::string& settings = spec.planners[1].settings_json;
  EXPECT_NE(settings.find(R"("profile":"paper")"), std::string::npos) << settings;
  const ParamValues p = plannerParameterSettings(settings);
  EXPECT_FALSE(p.contains("profile"));
  EXPECT_EQ(p.at("complete_pass"), "false");
  EXPECT_EQ(p.at("greedy_move_pruning"), "false");
  EXPECT_EQ(p.at("validator_rechecks"), "2");  // given explicitly: wins over the profile's 0
  EXPECT_EQ(resolveParameters("dash", p).at("one_object_pass"), "false");
  const std::string msg = expectError(edit(R"({"name": "lazy-dash"})", R"({"name": "dash", "profile": "fast"})"),
                                      SpecErrorKind::kBadValue);
  EXPECT_NE(msg.find("planners[1].profile"), std::string::npos) << msg;
}

// Unlabelled, a planner with a profile is labelled by its name, its profile and the settings given,
// not by the profile's expanded parameters; so two profiles of one planner are two configurations.
TEST(BatchSpec, AnUnlabelledPlannersLabelNamesItsProfileAndItsGivenSettings) {
  const BatchSpec spec = parseBatchSpec(
      edit(R"({"name": "lazy-dash"})",
           R"({"name": "lazy-dash", "profile": "paper"}, {"name": "lazy-dash", "profile": "default", "settings": {"clearance": 0.005}})"),
      "spec.json", kFast);
  ASSERT_EQ(spec.planners.size(), 3u);
  EXPECT_EQ(spec.planners[0].label, "lazy-task");
  EXPECT_EQ(spec.planners[1].label, "lazy-dash (paper)");
  EXPECT_EQ(spec.planners[2].label, "lazy-dash (default) {\"clearance\":0.005}");
}

TEST(BatchSpecErrors, MissingKeys) {
  const std::string msg = expectError(edit(R"("name": "tiny",)", ""), SpecErrorKind::kMissingKey);
  EXPECT_NE(msg.find("name"), std::string::npos) << msg;
  expectError(edit(R"({"from": 3, "count": 2})", R"({"from": 3})"), SpecErrorKind::kMissingKey);
}

TEST(BatchSpecErrors, EmptyGrids) {
  std::string msg = expectError(edit(R"([{"family": "sorting", "params": {"robots": 4, "objects": [4, 8]}}])", "[]"),
                                SpecErrorKind::kEmptyGrid);
  EXPECT_NE(msg.find("scenarios"), std::string::npos) << msg;
  msg = expectError(edit(R"("objects": [4, 8])", R"("objects": [])"), SpecErrorKind::kEmptyGrid);
  EXPECT_NE(msg.find("scenarios[0].params.objects"), std::string::npos) << msg;
  expectError(edit(R"({"from": 3, "count": 2})", "[]"), SpecErrorKind::kEmptyGrid);
  expectError(edit(R"({"from": 3, "count": 2})", R"({"from": 3, "count": 0})"), SpecErrorKind::kEmptyGrid);
  std::string s = validSpec();
  const auto p = s.find(R"("planners": [)");
  const auto e = s.find(R"("seeds")");
  s.replace(p, e - p, R"("planners": [], )");
  expectError(s, SpecErrorKind::kEmptyGrid);
}

TEST(BatchSpecErrors, ParametersOutOfTheRegistrysRange) {
  std::string msg = expectError(edit(R"("robots": 4)", R"("robots": [4, 70])"), SpecErrorKind::kOutOfRange);
  EXPECT_NE(msg.find("scenarios[0].params.robots[1]"), std::string::npos) << msg;
  EXPECT_NE(msg.find("2..64"), std::string::npos) << msg;  // the registry's range
  expectError(edit(R"("objects": [4, 8])", R"("objects": 0)"), SpecErrorKind::kOutOfRange);
  // shelf-wall robots must be even.
  msg = expectError(edit(R"({"family": "sorting", "params": {"robots": 4, "objects": [4, 8]}})",
                         R"({"family": "shelf-wall", "params": {"robots": 3}})"),
                    SpecErrorKind::kOutOfRange);
  EXPECT_NE(msg.find("even"), std::string::npos) << msg;
  expectError(edit(R"({"from": 3, "count": 2})", "[1, -2]"), SpecErrorKind::kOutOfRange);
}

TEST(BatchSpecErrors, UnknownFamily) {
  const std::string msg =
      expectError(edit(R"("family": "sorting")", R"("family": "juggling")"), SpecErrorKind::kUnknownFamily);
  EXPECT_NE(msg.find("sorting"), std::string::npos) << msg;  // lists the known ones
}

TEST(BatchSpecErrors, CombinationsTheGeneratorRefuses) {
  // Every value is in range, but 6 walls need 7 robots (walls <= robots - 1).
  const std::string text = edit(R"({"family": "sorting", "params": {"robots": 4, "objects": [4, 8]}})",
                                R"({"family": "wall", "params": {"robots": 5, "walls": [2, 6], "objects": 8}})");
  const std::string msg = expectError(text, SpecErrorKind::kBadCombination, SpecOptions{});
  EXPECT_NE(msg.find("walls=6"), std::string::npos) << msg;
  // Without probing, the same spec passes (the run itself would fail).
  EXPECT_NO_THROW(parseBatchSpec(text, "spec.json", kFast));
}

TEST(BatchSpecErrors, UnknownPlanner) {
  const std::string text = edit(R"({"name": "lazy-dash"})", R"({"name": "quantum-dash"})");
  const std::string msg = expectError(text, SpecErrorKind::kUnknownPlanner);
  EXPECT_NE(msg.find("quantum-dash"), std::string::npos) << msg;
  EXPECT_NE(msg.find("lazy-dash"), std::string::npos) << msg;  // what this build has
  // Collected instead of thrown on request.
  const BatchSpec spec =
      parseBatchSpec(text, "spec.json", SpecOptions{.allow_unknown_planners = true, .check_combinations = false});
  EXPECT_EQ(spec.unknown_planners, std::vector<std::string>({"quantum-dash"}));
}

TEST(BatchSpecErrors, BadValues) {
  expectError(edit(R"("time_limit": 5)", R"("time_limit": 0)"), SpecErrorKind::kBadValue);
  expectError(edit(R"("memory_limit": 1024)", R"("memory_limit": 10)"), SpecErrorKind::kBadValue);
  expectError(edit(R"("label": "lazy-task")", R"("label": "lazy-dash")"), SpecErrorKind::kBadValue);  // twice
  expectError(edit(R"("objects": [4, 8])", R"("objects": [4, 4])"), SpecErrorKind::kBadValue);
  expectError(edit(R"({"task_only": true})", R"({"test_fault": "explode"})"), SpecErrorKind::kBadValue);
  // Two scenario entries that list the same scene would give one key twice.
  expectError(edit(R"({"family": "sorting", "params": {"robots": 4, "objects": [4, 8]}})",
                   R"({"family": "sorting", "params": {"robots": 4, "objects": [4, 8]}},
                      {"family": "sorting", "params": {"robots": 4, "objects": 8}})"),
              SpecErrorKind::kBadValue);
}

TEST(BatchSpecErrors, TooManyRuns) {
  // 8 runs against a limit of 7.
  std::string msg =
      expectError(validSpec(), SpecErrorKind::kTooManyRuns, SpecOptions{.max_runs = 7, .check_combinations = false});
  EXPECT_NE(msg.find("8 runs"), std::string::npos) << msg;
  // The default limit is 10,000: 31 robot counts x 128 object counts x 3 seeds x 1 planner = 11,904.
  msg = expectError(R"({"name":"big","scenarios":[{"family":"sorting","params":{"robots":[)" +
                        [] {
                          std::string v;
                          for (int r = 2; r <= 32; ++r) v += (r == 2 ? "" : ",") + std::to_string(r);
                          v += R"(],"objects":[)";
                          for (int o = 1; o <= 128; ++o) v += (o == 1 ? "" : ",") + std::to_string(o);
                          return v;
                        }() +
                        R"(]}}],"planners":[{"name":"lazy-dash"}],"seeds":[1,2,3]})",
                    SpecErrorKind::kTooManyRuns, SpecOptions{});
  EXPECT_NE(msg.find("10000"), std::string::npos) << msg;
}

}  // namespace
}  // namespace dash::batch

namespace dash::batch {
namespace {

// Issue 24: numbers that overflowed the runner's and Slurm's arithmetic, and a seed list whose
// duplicate check was quadratic.
TEST(BatchSpecErrors, NumbersHaveUpperBounds) {
  expectError(edit(R"("time_limit": 5)", R"("time_limit": 1e10)"), SpecErrorKind::kBadValue);
  expectError(edit(R"("memory_limit": 1024)", R"("memory_limit": 1e30)"), SpecErrorKind::kBadValue);
  expectError(edit(R"("seeds": {"from": 3, "count": 2})", R"("seeds": {"from": 9223372036854775000, "count": 2})"),
              SpecErrorKind::kOutOfRange);
  expectError(edit(R"("seeds": {"from": 3, "count": 2})", R"("seeds": [1, 9007199254740993])"),
              SpecErrorKind::kOutOfRange);
  std::string many = "[";
  for (int i = 0; i < 1000001; ++i) many += std::to_string(i) + ",";
  many.back() = ']';
  expectError(edit(R"("seeds": {"from": 3, "count": 2})", R"("seeds": )" + many), SpecErrorKind::kTooManyRuns);
  EXPECT_NO_THROW(parseBatchSpec(edit(R"("time_limit": 5)", R"("time_limit": 604800)"), "spec.json", kFast));
}

TEST(BatchSpec, CountRunsSaturatesInsteadOfWrapping) {
  BatchSpec spec;
  ScenarioEntry e{.family = "sorting"};
  for (int p = 0; p < 5; ++p) e.params.emplace_back("p" + std::to_string(p), std::vector<int>(1 << 14, 1));
  spec.scenarios.push_back(e);
  spec.seeds.assign(4, 1);
  spec.planners.resize(2);
  EXPECT_EQ(countRuns(spec), std::numeric_limits<std::size_t>::max());
}

}  // namespace
}  // namespace dash::batch
