// A run of each real planner (Lazy-DaSH and DaSH) recorded in a results database: the vertices and
// hyperarcs its events add (net of removals) per layer equal the final representation sizes the
// planner reports, and so do the sizes finishRun derives into dash_runs and the Planner Arena view.
// (tests/dash checks the same against the in-memory sink; this is the database's side.)
#include <gtest/gtest.h>

#include <array>
#include <map>
#include <string>
#include <utility>

#include "engine/log/results_db.h"
#include "engine/log/sqlite_recorder.h"
#include "engine/planners/planner.h"
#include "engine/robots/robot_model.h"
#include "engine/scenarios/scenario_registry.h"
#include "tests/log/log_test_util.h"

namespace dash::log {
namespace {

using KeyValues = std::vector<std::pair<std::string, std::string>>;

struct Case {
  std::string planner;
  std::string family;
  KeyValues params;
};

void PrintTo(const Case& c, std::ostream* os) { *os << c.planner << " on " << c.family; }

/// The reported sizes, indexed like the database's layers.
std::array<std::pair<std::int64_t, std::int64_t>, kLayerCount> reportedSizes(const RepresentationCounts& n) {
  auto i = [](std::size_t v) { return static_cast<std::int64_t>(v); };
  return {{{i(n.task_vertices), i(n.task_hyperarcs)},
           {i(n.task_extended_vertices), i(n.task_extended_hyperarcs)},
           {i(n.motion_vertices), i(n.motion_hyperarcs)},
           {i(n.motion_extended_vertices), i(n.motion_extended_hyperarcs)}}};
}

std::int64_t integer(const SqlValue& v) {
  return std::holds_alternative<std::int64_t>(v) ? std::get<std::int64_t>(v) : -1;
}

class PlannerDatabase : public ::testing::TestWithParam<Case> {};

/// Plans case `c` (seed 1) with a recorder of a new run in the database at `path`; the result and the run's uuid.
std::pair<PlanResult, std::string> planAndRecord(const Case& c, const std::string& path) {
  const Scene scene = generateScenario(c.family, c.params, 1, RobotLibrary::loadDefault());
  std::string params_json = "{";
  for (const auto& [k, v] : c.params) params_json += (params_json.size() > 1 ? "," : "") + ("\"" + k + "\":" + v);
  params_json += "}";
  PlannerSettings settings;
  settings.seed = 1;
  settings.time_limit = 60;

  PlanResult result;
  std::string uuid;
  ResultsDb db(path);
  uuid = db.beginRun(RunMetadata{.family = c.family,
                                 .params_json = params_json,
                                 .seed = 1,
                                 .planner = c.planner,
                                 .time_limit = settings.time_limit});
  {
    auto recorder = db.recorder(uuid);
    result = makePlanner(c.planner)->solve(scene, settings, Deadline(settings.time_limit), recorder.get());
  }
  // Sizes left unset: finishRun derives them from the stored events.
  db.finishRun(uuid, RunSummary{.status = result.outcome == PlanOutcome::kSolved ? RunStatus::Solved
                                                                                : RunStatus::Timeout});
  return {std::move(result), uuid};
}

/// Conflict resolution's progress: its snapshots count steps of one plan's total, and the last build
/// (the solved plan's) ended with every step scheduled.
void expectConflictResolutionProgress(const ResultsDb& db, std::int64_t run_id) {
  const SqlRows work = db.select("SELECT progress_done, progress_total, progress_current FROM dash_progress WHERE "
                                 "run_id = ? AND progress_phase = 'conflict_resolution' ORDER BY t",
                                 {run_id});
  ASSERT_FALSE(work.rows.empty());
  for (const auto& row : work.rows) {
    EXPECT_GT(integer(row[1]), 0);
    EXPECT_GE(integer(row[0]), 0);
    EXPECT_LE(integer(row[0]), integer(row[1]));
  }
  EXPECT_EQ(integer(work.rows.back()[0]), integer(work.rows.back()[1]));
  EXPECT_EQ(work.rows.back()[2], SqlValue());
}

TEST_P(PlannerDatabase, EventCountsEqualTheReportedRepresentationSizes) {
  const Case& c = GetParam();
  testing::TempDir dir;
  const std::string path = dir.file("results.db");
  const auto [result, uuid] = planAndRecord(c, path);
  // Small scenes both planners solve quickly (tests/dash): a run that stops early is a failure here.
  ASSERT_EQ(result.outcome, PlanOutcome::kSolved) << c.planner << ": " << result.message;
  const auto reported = reportedSizes(result.stats.sizes);

  const ResultsDb db(path, OpenMode::ReadOnly);
  const std::optional<RunRecord> run = db.getRun(uuid);
  ASSERT_TRUE(run.has_value());
  // Net elements per (layer, kind), straight from the event table.
  std::map<std::pair<std::string, std::string>, std::int64_t> stored;
  for (const auto& row : db.select("SELECT layer, kind, SUM(CASE change WHEN 'added' THEN 1 ELSE -1 END) "
                                   "FROM dash_events WHERE run_id = ? GROUP BY layer, kind",
                                   {run->id})
                             .rows) {
    stored[{std::get<std::string>(row[0]), std::get<std::string>(row[1])}] = integer(row[2]);
  }
  ASSERT_TRUE(run->summary.sizes.has_value());
  for (int l = 0; l < kLayerCount; ++l) {
    SCOPED_TRACE(std::string(c.planner) + ", layer " + kLayerNames[static_cast<std::size_t>(l)]);
    const auto [vertices, hyperarcs] = reported[static_cast<std::size_t>(l)];
    const std::string layer = kLayerNames[static_cast<std::size_t>(l)];
    EXPECT_EQ(stored[std::make_pair(layer, std::string("vertex"))], vertices);
    EXPECT_EQ(stored[std::make_pair(layer, std::string("hyperarc"))], hyperarcs);
    EXPECT_EQ(run->summary.sizes->vertices[static_cast<std::size_t>(l)], vertices);
    EXPECT_EQ(run->summary.sizes->hyperarcs[static_cast<std::size_t>(l)], hyperarcs);
  }
  // The layers each planner must have built (so that the equalities above are not 0 == 0).
  EXPECT_GT(reported[0].first, 0);   // H_T vertices
  EXPECT_GT(reported[0].second, 0);  // H_T hyperarcs
  EXPECT_GT(reported[2].first, 0);   // H_M vertices
  if (c.planner == "lazy-dash") {
    EXPECT_GT(reported[1].first, 0);  // H_TE vertices
  } else {
    EXPECT_GT(reported[2].second, 0);  // DaSH's eager H_M
  }

  // Planner Arena's runs view shows the same final sizes.
  const SqlRows arena = db.select(
      "SELECT task_vertices, task_hyperarcs, motion_vertices, motion_hyperarcs FROM runs WHERE id = ?", {run->id});
  ASSERT_EQ(arena.rows.size(), 1u);
  EXPECT_EQ(integer(arena.rows[0][0]), reported[0].first);
  EXPECT_EQ(integer(arena.rows[0][1]), reported[0].second);
  EXPECT_EQ(integer(arena.rows[0][2]), reported[2].first);
  EXPECT_EQ(integer(arena.rows[0][3]), reported[2].second);

  ASSERT_NO_FATAL_FAILURE(expectConflictResolutionProgress(db, run->id));
}

INSTANTIATE_TEST_SUITE_P(
    EachPlanner, PlannerDatabase,
    ::testing::Values(Case{"lazy-dash", "sorting", {{"robots", "2"}, {"objects", "2"}}},
                      Case{"lazy-dash", "lab", {{"containers", "2"}}},
                      Case{"dash", "sorting", {{"robots", "2"}, {"objects", "2"}}},
                      Case{"dash", "lab", {{"containers", "2"}}}),
    [](const ::testing::TestParamInfo<Case>& info) {
      std::string name = info.param.planner + "_" + info.param.family;
      for (const auto& [k, v] : info.param.params) name += "_" + k + v;
      for (char& ch : name) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return name;
    });

}  // namespace
}  // namespace dash::log
