#include <gtest/gtest.h>

#include "engine/scenarios/scenario_registry.h"
#include "scenario_test_util.h"

namespace dash {
namespace {

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ScenarioParams, DefaultsAndOverridesInFamilyOrder) {
  const auto& specs = scenarioFamily("sorting").params;
  const ScenarioParams d = resolveParams("sorting", specs, {});
  EXPECT_EQ(d.get("robots"), 4);
  EXPECT_EQ(d.get("objects"), 8);
  const ScenarioParams p = resolveParams("sorting", specs, {{"objects", "20"}, {"robots", "6"}});
  ASSERT_EQ(p.values().size(), 2u);
  EXPECT_EQ(p.values()[0], std::make_pair(std::string("robots"), 6));
  EXPECT_EQ(p.values()[1], std::make_pair(std::string("objects"), 20));
}

TEST(ScenarioParams, UnknownKeyNamesTheKeyAndTheKnownOnes) {
  const std::string e = errorOf([] { resolveParams("sorting", scenarioFamily("sorting").params, {{"arms", "3"}}); });
  EXPECT_NE(e.find("unknown parameter 'arms'"), std::string::npos) << e;
  EXPECT_NE(e.find("robots (2..64)"), std::string::npos) << e;
}

TEST(ScenarioParams, OutOfRangeNamesTheKeyAndTheRange) {
  const auto& specs = scenarioFamily("sorting").params;
  std::string e = errorOf([&] { resolveParams("sorting", specs, {{"robots", "65"}}); });
  EXPECT_NE(e.find("robots"), std::string::npos) << e;
  EXPECT_NE(e.find("2..64"), std::string::npos) << e;
  e = errorOf([&] { resolveParams("sorting", specs, {{"objects", "0"}}); });
  EXPECT_NE(e.find("objects"), std::string::npos) << e;
  EXPECT_NE(e.find("1..256"), std::string::npos) << e;
}

TEST(ScenarioParams, NotAnIntegerOrOddWhereEvenIsNeeded) {
  std::string e = errorOf([] { resolveParams("lab", scenarioFamily("lab").params, {{"containers", "2.5"}}); });
  EXPECT_NE(e.find("not an integer"), std::string::npos) << e;
  e = errorOf([] { resolveParams("lab", scenarioFamily("lab").params, {{"containers", ""}}); });
  EXPECT_NE(e.find("not an integer"), std::string::npos) << e;
  e = errorOf([] { resolveParams("shelf-wall", scenarioFamily("shelf-wall").params, {{"robots", "3"}}); });
  EXPECT_NE(e.find("must be even"), std::string::npos) << e;
  EXPECT_NE(e.find("2..8, even"), std::string::npos) << e;
}

TEST(ScenarioParams, UnknownFamilyListsTheFamilies) {
  const std::string e = errorOf([] { scenarioFamily("sortng"); });
  EXPECT_NE(e.find("unknown scenario family 'sortng'"), std::string::npos) << e;
  EXPECT_NE(e.find("shelf-wall"), std::string::npos) << e;
  EXPECT_EQ(findScenarioFamily("sortng"), nullptr);
  ASSERT_NE(findScenarioFamily("lab"), nullptr);
}

TEST(ScenarioParams, WallCountBoundByRobots) {
  const std::string e = errorOf([] { test::generate("wall", {{"robots", "4"}, {"walls", "4"}}, 1); });
  EXPECT_NE(e.find("walls=4 needs robots >= 5"), std::string::npos) << e;
  EXPECT_NO_THROW(test::generate("wall", {{"robots", "4"}, {"walls", "3"}}, 1));
}

TEST(ScenarioParams, ListShowsEveryFamilyWithDefaultsAndRanges) {
  const std::string list = describeScenarioFamilies();
  for (const auto& f : scenarioFamilies()) {
    EXPECT_NE(list.find(f.name + ": "), std::string::npos) << f.name;
    for (const auto& p : f.params) {
      EXPECT_NE(list.find(p.name + "=" + std::to_string(p.default_value) + "  (" + p.rangeText() + ")"),
                std::string::npos)
          << f.name << " " << p.name;
    }
  }
  ASSERT_EQ(scenarioFamilies().size(), 5u);
}

TEST(ScenarioParams, GeneratorRecordHoldsEveryParameterAndTheSeed) {
  const auto g = test::generate("wall", {{"objects", "12"}}, 77);
  ASSERT_TRUE(g.scene.generator.has_value());
  EXPECT_EQ(g.scene.generator->name, "wall");
  EXPECT_EQ(g.scene.generator->seed, 77u);
  ASSERT_EQ(g.scene.generator->params.size(), 3u);
  EXPECT_EQ(g.scene.generator->params[1].first, "objects");
  EXPECT_EQ(std::get<double>(g.scene.generator->params[1].second), 12.0);
  EXPECT_EQ(g.scene.name, "wall-r8-o12-w1-s77");
}

}  // namespace
}  // namespace dash
