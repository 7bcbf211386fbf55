// `dashbench report DB --figures DIR` on a small results database: the files exist and hold the
// expected panels and series, the time panels share one y range, skipped sizes are drawn.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "engine/core/check.h"
#include "server/figures/comparison_figures.h"
#include "tests/common/temp_dir.h"

namespace dash::figures {
namespace {

using test::TempDir;

/// One finished run: sizes and phase seconds scaled by `k`.
void addRun(log::ResultsDb& db, const std::string& family, const std::string& params, std::uint64_t seed,
            const std::string& planner, log::RunStatus status, double k, const std::string& label = "",
            const std::string& settings = "{}") {
  const std::string uuid = db.beginRun(log::RunMetadata{.batch_id = "b1", .family = family, .params_json = params,
                                                        .seed = seed, .planner = planner,
                                                        .planner_settings_json = settings,
                                                        .planner_config_name = label.empty() ? planner : label});
  log::RunSummary s;
  s.status = status;
  s.total_time = 6 * k;
  log::PhaseTotals phases{};
  phases[static_cast<int>(log::Phase::TaskConstruction)] = 0.5 * k;
  phases[static_cast<int>(log::Phase::MotionConstruction)] = 1.5 * k;
  phases[static_cast<int>(log::Phase::MotionQuery)] = 2 * k;
  phases[static_cast<int>(log::Phase::ConflictResolution)] = 2 * k;
  s.phase_seconds = phases;
  log::RepresentationSizes sizes;
  for (int layer = 0; layer < log::kLayerCount; ++layer) {
    sizes.vertices[layer] = static_cast<std::int64_t>(10 * k);
    sizes.hyperarcs[layer] = static_cast<std::int64_t>(100 * k);
  }
  s.sizes = sizes;
  db.finishRun(uuid, s);
}

std::string read(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> attributes(const std::string& svg, const std::string& cls, const std::string& attr) {
  std::vector<std::string> out;
  const std::regex re("class=\"" + cls + "\" " + attr + "=\"([^\"]*)\"");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

class Figures : public ::testing::Test {
 protected:
  void SetUp() override {
    log::ResultsDb db(dir.file("r.db"));
    db.putBatch(log::BatchRecord{.id = "b1", .name = "figs", .spec_json = "{}", .status = "finished"});
    for (std::uint64_t seed : {1, 2}) {
      for (int objects : {2, 4}) {
        const std::string params = R"({"robots":4,"objects":)" + std::to_string(objects) + "}";
        addRun(db, "sorting", params, seed, "lazy-dash", log::RunStatus::Solved, objects);
        addRun(db, "sorting", params, seed, "dash", objects == 4 ? log::RunStatus::Timeout : log::RunStatus::Solved,
               10.0 * objects);
      }
      addRun(db, "lab", R"({"containers":1})", seed, "lazy-dash", log::RunStatus::Solved, 1);
      addRun(db, "lab", R"({"containers":2})", seed, "lazy-dash", log::RunStatus::Solved, 2);
    }
    db.flush();
  }
  TempDir dir;
};

TEST_F(Figures, EveryFamilyGetsItsThreeFiguresAsSvgAndPng) {
  const log::ResultsDb db(dir.file("r.db"), log::OpenMode::ReadOnly);
  const FigureFiles files = writeComparisonFigures(db, FigureOptions{.batch_id = "b1", .dir = dir.file("figs")});
  EXPECT_EQ(files.families, (std::vector<std::string>{"sorting", "lab"}));
  EXPECT_EQ(files.files.size(), 12u);
  for (const char* family : {"sorting", "lab"})
    for (const char* what : {"sizes", "time", "success"})
      for (const char* ext : {".svg", ".png"}) {
        const std::string path = dir.file("figs/" + std::string(family) + "-" + what + ext);
        ASSERT_TRUE(std::filesystem::exists(path)) << path;
        EXPECT_GT(std::filesystem::file_size(path), 500u) << path;
      }
  EXPECT_EQ(read(dir.file("figs/lab-time.png")).substr(1, 3), "PNG");

  const std::string sizes = read(dir.file("figs/sorting-sizes.svg"));
  EXPECT_EQ(attributes(sizes, "panel", "data-title"),
            (std::vector<std::string>{"H_T vertices", "H_T hyperarcs", "H_M vertices", "H_M hyperarcs"}));
  const std::vector<std::string> series = attributes(sizes, "series", "data-name");
  EXPECT_EQ(std::set<std::string>(series.begin(), series.end()), (std::set<std::string>{"dash", "lazy-dash"}));
  EXPECT_EQ(series.size(), 8u);  // two planners in each of four panels
  EXPECT_NE(sizes.find("log scale"), std::string::npos);
  EXPECT_NE(sizes.find("problem size: objects (count)"), std::string::npos);

  const std::string time = read(dir.file("figs/sorting-time.svg"));
  EXPECT_EQ(attributes(time, "panel", "data-title"),
            (std::vector<std::string>{"construction (task + motion)", "query (task + motion)", "conflict resolution",
                                      "total"}));
  EXPECT_NE(time.find("time (s, log scale)"), std::string::npos);
  // Success as grouped bars, one per planner and size; DaSH's 0 % at objects=4 is a bar, not a gap.
  const std::string success = read(dir.file("figs/sorting-success.svg"));
  EXPECT_EQ(attributes(success, "bar", "data-x").size(), 4u);
  EXPECT_NE(success.find(R"(class="bar" data-x="4" data-y="0")"), std::string::npos);
  EXPECT_EQ(attributes(sizes, "bar", "data-x").size(), 0u);  // sizes stay lines
  // Lab's size axis is its containers (objects does not vary there).
  EXPECT_NE(read(dir.file("figs/lab-success.svg")).find("problem size: containers (count)"), std::string::npos);
}

TEST_F(Figures, TimePanelsShareOneRangeAndSuccessCountsUnsolvedRuns) {
  const log::ResultsDb db(dir.file("r.db"), log::OpenMode::ReadOnly);
  const FigureRuns runs = collectFigureRuns(db, "b1");
  ASSERT_EQ(runs.families.size(), 2u);
  const FamilyData& sorting = runs.families[0];
  EXPECT_EQ(sorting.x_param, "objects");
  const Figure time = timeFigure(sorting);
  ASSERT_EQ(time.panels.size(), 4u);
  for (const Panel& p : time.panels) {
    ASSERT_TRUE(p.y_range.has_value());
    EXPECT_EQ(*p.y_range, *time.panels[0].y_range);
  }
  // Largest value: dash's total at objects=2, 6 * 20 = 120 s -> the range reaches 1000 s.
  EXPECT_DOUBLE_EQ(time.panels[0].y_range->second, 1000.0);
  const Figure success = successFigure(sorting);
  for (const Series& s : success.panels[0].series) {
    if (s.name != "dash") continue;
    EXPECT_EQ(s.points, (std::vector<std::pair<double, double>>{{2, 100.0}, {4, 0.0}}));
  }
  // Sizes are medians over solved runs only: dash has no point at objects=4.
  const Figure sizes = sizeFigure(sorting);
  for (const Series& s : sizes.panels[0].series)
    if (s.name == "dash") {
      EXPECT_EQ(s.points.size(), 1u);
    }
}

TEST_F(Figures, SkippedSizesAreDrawnAndAnEmptyBatchIsAnError) {
  // A skipped run as the batch runner records it (server/batch/batch_store.h).
  {
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(dir.file("r.db").c_str(), &raw), SQLITE_OK);
    auto exec = [&](const std::string& sql) { EXPECT_EQ(sqlite3_exec(raw, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK) << sql; };
    exec(
        "CREATE TABLE IF NOT EXISTS dash_batch_runs (batch_id TEXT, run_key TEXT, ordinal INTEGER, spec TEXT, "
        "run_uuid TEXT, attempts INTEGER)");
    exec("CREATE TABLE IF NOT EXISTS dash_batch_skipped (batch_id TEXT, run_key TEXT, reason TEXT)");
    exec(
        "INSERT INTO dash_batch_runs VALUES ('b1', 'k', 9, '{\"family\":\"sorting\",\"params\":[[\"robots\",4],"
        "[\"objects\",8]],\"label\":\"dash\"}', NULL, 0)");
    exec("INSERT INTO dash_batch_skipped VALUES ('b1', 'k', 'dash solved none of the 2 runs at objects=4')");
    sqlite3_close(raw);
  }
  const log::ResultsDb db(dir.file("r.db"), log::OpenMode::ReadOnly);
  const FigureFiles files = writeComparisonFigures(db, FigureOptions{.batch_id = "b1", .dir = dir.file("f"), .png = false});
  EXPECT_EQ(files.files.size(), 6u);
  const std::string success = read(dir.file("f/sorting-success.svg"));
  EXPECT_NE(success.find("class=\"skipped\""), std::string::npos);
  EXPECT_NE(success.find("not run (failed a smaller size on every seed)"), std::string::npos);
  EXPECT_THROW(writeComparisonFigures(db, FigureOptions{.batch_id = "nope", .dir = dir.file("g"), .png = false}),
               InputError);
}

// Lines are ordered by the values of the parameters that name them, as numbers (robots=4, 8, 16), and
// within one group by planner in the order the batch ran them.
TEST(FigureLines, GroupsFollowTheirParameterValuesAsNumbers) {
  TempDir dir;
  {
    log::ResultsDb db(dir.file("r.db"));
    db.putBatch(log::BatchRecord{.id = "b1", .name = "figs", .spec_json = "{}", .status = "finished"});
    for (int robots : {16, 4, 8})
      for (int objects : {2, 4, 8, 14, 16, 64})
        for (const char* planner : {"lazy-dash", "dash"})
          addRun(db, "sorting", R"({"robots":)" + std::to_string(robots) + R"(,"objects":)" + std::to_string(objects) + "}",
                 1, planner, log::RunStatus::Solved, 1);
    db.flush();
  }
  const log::ResultsDb db(dir.file("r.db"), log::OpenMode::ReadOnly);
  const FigureRuns runs = collectFigureRuns(db, "b1");
  ASSERT_EQ(runs.families.size(), 1u);
  std::vector<std::string> names;
  for (const Line& l : runs.families[0].lines) names.push_back(l.name());
  EXPECT_EQ(names, (std::vector<std::string>{"lazy-dash robots=4", "dash robots=4", "lazy-dash robots=8", "dash robots=8",
                                             "lazy-dash robots=16", "dash robots=16"}));
  // On an axis to 64, 14 and 16 are too close for both labels: 16's is left out, its tick stays.
  writeComparisonFigures(db, FigureOptions{.batch_id = "b1", .dir = dir.file("figs"), .png = false});
  const std::string sizes = read(dir.file("figs/sorting-sizes.svg"));
  auto count = [&](const std::string& text) {
    std::size_t n = 0;
    for (auto at = sizes.find(text); at != std::string::npos; at = sizes.find(text, at + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count(">14</text>"), 4u);  // one per panel
  EXPECT_EQ(count(">16</text>"), 0u);
  EXPECT_EQ(count(">64</text>"), 4u);
}


// A series says the profile its runs ran under (`--profile`, in the run's settings) unless its label
// names it, skipped runs included: one batch's two profiles of a planner are two named lines.
TEST(FigureLines, EachSeriesNamesTheProfileItsRunsRanUnder) {
  TempDir dir;
  {
    log::ResultsDb db(dir.file("r.db"));
    db.putBatch(log::BatchRecord{.id = "b1", .name = "figs", .spec_json = "{}", .status = "finished"});
    const std::string params = R"({"robots":4,"objects":2})";
    addRun(db, "sorting", params, 1, "dash", log::RunStatus::Solved, 1, "dash", R"({"profile":"default"})");
    addRun(db, "sorting", params, 1, "dash", log::RunStatus::Timeout, 1, "dash-paper", R"({"profile":"paper"})");
    addRun(db, "sorting", params, 1, "lazy-dash", log::RunStatus::Solved, 1, "lazy-dash", R"({"profile":"paper"})");
    addRun(db, "sorting", params, 1, "lazy-dash", log::RunStatus::Solved, 1, "old", "{}");
    sqlite3* raw = nullptr;
    ASSERT_EQ(sqlite3_open(dir.file("r.db").c_str(), &raw), SQLITE_OK);
    for (const char* sql :
         {"CREATE TABLE IF NOT EXISTS dash_batch_runs (batch_id TEXT, run_key TEXT, ordinal INTEGER, spec TEXT, "
          "run_uuid TEXT, attempts INTEGER)",
          "CREATE TABLE IF NOT EXISTS dash_batch_skipped (batch_id TEXT, run_key TEXT, reason TEXT)",
          "INSERT INTO dash_batch_runs VALUES ('b1', 'k', 9, '{\"family\":\"sorting\",\"params\":[[\"robots\",4],"
          "[\"objects\",4]],\"label\":\"dash\",\"settings\":{\"profile\":\"default\"}}', NULL, 0)",
          "INSERT INTO dash_batch_skipped VALUES ('b1', 'k', 'dash solved none of the runs at objects=2')"})
      EXPECT_EQ(sqlite3_exec(raw, sql, nullptr, nullptr, nullptr), SQLITE_OK) << sql;
    sqlite3_close(raw);
  }
  const log::ResultsDb db(dir.file("r.db"), log::OpenMode::ReadOnly);
  const FigureRuns runs = collectFigureRuns(db, "b1");
  ASSERT_EQ(runs.families.size(), 1u);
  std::vector<std::string> names;
  for (const Line& l : runs.families[0].lines) names.push_back(l.name());
  EXPECT_EQ(names, (std::vector<std::string>{"dash (default)", "dash-paper", "lazy-dash (paper)", "old"}));
  EXPECT_EQ(runs.families[0].lines[0].skipped.count(4), 1u);  // the skipped run is on dash (default)
}

TEST_F(Figures, CommandLineFiguresUseTheDashboardsPalette) {
  const log::ResultsDb db(dir.file("r.db"), log::OpenMode::ReadOnly);
  writeComparisonFigures(db, FigureOptions{.batch_id = "b1", .dir = dir.file("figs"), .png = false});
  const std::string sizes = read(dir.file("figs/sorting-sizes.svg"));
  // Okabe & Ito's first two colours, as web/js/palette.js has them; not matplotlib's.
  EXPECT_NE(sizes.find("\"#0072B2\""), std::string::npos);
  EXPECT_NE(sizes.find("\"#E69F00\""), std::string::npos);
  EXPECT_EQ(sizes.find("#1f77b4"), std::string::npos);
}

TEST(SvgChart, TickLabelsAreWrittenWithoutExponents) {
  Figure f;
  Panel p;
  p.title = "t";
  p.log_y = true;
  p.series.push_back(Series{.name = "s", .points = {{1, 0.001}, {2, 20000}}});
  f.panels.push_back(p);
  const std::string svg = renderSvg(f);
  for (const char* label : {">0.001</text>", ">0.01</text>", ">1</text>", ">10,000</text>", ">100,000</text>"})
    EXPECT_NE(svg.find(label), std::string::npos) << label << "\n" << svg;
  EXPECT_EQ(svg.find(">1e"), std::string::npos) << svg;
  EXPECT_EQ(tickLabel(0.0005), "0.0005");
  EXPECT_EQ(tickLabel(0.00123), "0.00123");
  EXPECT_EQ(tickLabel(0.25), "0.25");
  EXPECT_EQ(tickLabel(1234567), "1,234,567");
}

}  // namespace
}  // namespace dash::figures
