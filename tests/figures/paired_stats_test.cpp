// The paired statistics (server/figures/paired_stats.h) on the hand-worked cases that the Compare
// page's JavaScript is checked against too (tests/figures/paired_stats_cases.json, web_units.mjs):
// the same data gives the same numbers in both languages.
#include "server/figures/paired_stats.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

namespace dash::figures {
namespace {

nlohmann::json cases() {
  std::ifstream in(std::string(DASHBENCH_SOURCE_DIR) + "/tests/figures/paired_stats_cases.json");
  return nlohmann::json::parse(in);
}

log::RunRecord runOf(const nlohmann::json& j) {
  log::RunRecord r;
  r.status = log::parseRunStatus(j.at("status").get<std::string>());
  r.summary.total_time = j.at("total_time").get<double>();
  r.meta.time_limit = j.at("time_limit").get<double>();
  return r;
}

void expectNear(std::optional<double> actual, const nlohmann::json& expected, const std::string& what) {
  if (expected.is_null()) {
    EXPECT_FALSE(actual.has_value()) << what;
    return;
  }
  ASSERT_TRUE(actual.has_value()) << what;
  const double e = expected.get<double>();
  EXPECT_NEAR(*actual, e, 1e-9 * std::max(1.0, std::fabs(e))) << what;
}

TEST(PairedStats, StudentQuantilesMatchTheTable) {
  for (const auto& row : cases().at("t_quantiles")) {
    const double p = row[0], df = row[1], t = row[2];
    EXPECT_NEAR(studentQuantile(p, df), t, 1e-9 * t) << "t(" << p << "; " << df << ")";
  }
}

TEST(PairedStats, HandCheckedCasesGiveTheRatioIntervalCensoredSignTestAndWilsonIntervals) {
  for (const auto& c : cases().at("cases")) {
    const std::string name = c.at("name");
    std::vector<std::pair<Observation, Observation>> pairs;
    for (const auto& p : c.at("pairs")) pairs.emplace_back(observe(runOf(p[0])), observe(runOf(p[1])));
    const PairedStats s = pairedStats(pairs);
    const auto& e = c.at("expected");
    EXPECT_EQ(s.pairs, e.at("pairs").get<int>()) << name;
    EXPECT_EQ(s.both_solved, e.at("both_solved").get<int>()) << name;
    EXPECT_EQ(s.a_faster, e.at("a_faster").get<int>()) << name;
    EXPECT_EQ(s.b_faster, e.at("b_faster").get<int>()) << name;
    EXPECT_EQ(s.undecided, e.at("undecided").get<int>()) << name;
    EXPECT_EQ(s.a_solved, e.at("a_solved").get<int>()) << name;
    EXPECT_EQ(s.b_solved, e.at("b_solved").get<int>()) << name;
    expectNear(s.ratio, e.at("ratio"), name + ": ratio");
    expectNear(s.ratio_low, e.at("ratio_low"), name + ": ratio low");
    expectNear(s.ratio_high, e.at("ratio_high"), name + ": ratio high");
    expectNear(s.p_value, e.at("p_value"), name + ": p");
    expectNear(s.a_success.low, e.at("a_low"), name + ": a low");
    expectNear(s.a_success.high, e.at("a_high"), name + ": a high");
    expectNear(s.b_success.low, e.at("b_low"), name + ": b low");
    expectNear(s.b_success.high, e.at("b_high"), name + ": b high");
  }
}

TEST(PairedStats, SignTestStaysFiniteForThousandsOfPairs) {
  EXPECT_DOUBLE_EQ(*signTestP(5000, 10000), 1.0);
  const double p = *signTestP(4900, 10000);  // the normal approximation gives 0.0466
  EXPECT_GT(p, 0.044);
  EXPECT_LT(p, 0.049);
  EXPECT_FALSE(signTestP(0, 0).has_value());
}

}  // namespace
}  // namespace dash::figures
