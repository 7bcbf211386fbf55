// Same inputs, same bytes; other seeds, other scenes; and the examples in data/scenes are reproduced
// byte for byte (which also catches a machine whose arithmetic differs).
#include <gtest/gtest.h>

#include "engine/core/paths.h"
#include "engine/scene/scene_json.h"
#include "scenario_test_util.h"
#include "tests/common/examples.h"

namespace dash {
namespace {

struct Case {
  std::string family;
  test::KeyValues params;
};

const std::vector<Case>& cases() {
  static const std::vector<Case> all = {
      {"sorting", {}},
      {"sorting", {{"robots", "6"}, {"objects", "17"}}},
      {"wall", {{"walls", "2"}, {"objects", "10"}}},
      {"shelf-wall", {{"robots", "4"}, {"objects", "9"}}},
      {"stocking", {{"layers", "3"}, {"objects", "10"}}},
      {"lab", {{"containers", "5"}}},
  };
  return all;
}

std::string json(const Case& c, std::uint64_t seed) {
  return sceneToJson(test::generate(c.family, c.params, seed).scene);
}

TEST(ScenarioDeterminism, SameSeedSameBytes) {
  for (const Case& c : cases()) {
    for (const std::uint64_t seed : {0ULL, 5ULL, 18446744073709551615ULL}) {
      EXPECT_EQ(json(c, seed), json(c, seed)) << c.family << " seed " << seed;
    }
  }
}

TEST(ScenarioDeterminism, OtherSeedOtherScene) {
  for (const Case& c : cases()) {
    const std::string a = json(c, 1);
    const std::string b = json(c, 2);
    EXPECT_NE(a, b) << c.family;
    // Not only the recorded seed and name differ: the layout does.
    const Scene sa = parseScene(a, test::library());
    const Scene sb = parseScene(b, test::library());
    bool layout_differs = false;
    for (std::size_t j = 0; j < sa.objects.size(); ++j) {
      layout_differs |= !sa.objects[j].X_WO_start.isApprox(sb.objects[j].X_WO_start);
    }
    EXPECT_TRUE(layout_differs) << c.family;
  }
}

TEST(ScenarioDeterminism, WrittenSceneReadsBackUnchanged) {
  for (const Case& c : cases()) {
    const auto g = test::generate(c.family, c.params, 11);
    const Scene back = parseScene(sceneToJson(g.scene), test::library());
    ASSERT_EQ(back.objects.size(), g.scene.objects.size());
    for (std::size_t j = 0; j < back.objects.size(); ++j) {
      EXPECT_TRUE(back.objects[j].X_WO_start.isApprox(g.scene.objects[j].X_WO_start, 1e-12)) << c.family;
    }
    ASSERT_EQ(back.obstacles.size(), g.scene.obstacles.size());
    EXPECT_EQ(back.surfaces.size(), g.scene.surfaces.size());
    EXPECT_EQ(back.tasks.size(), g.scene.tasks.size());
  }
}

// The example of each family in data/scenes was written by
// `dashbench scenario FAMILY --seed 1 -o data/scenes/FAMILY.json` with default parameters.
TEST(ScenarioDeterminism, ExamplesInDataAreReproduced) {
  for (const auto& f : scenarioFamilies()) {
    const std::string path = dataDirectory() + "/scenes/" + f.name + ".json";
    const std::string stored = test::readFile(path);
    ASSERT_FALSE(stored.empty()) << path;
    EXPECT_EQ(sceneToJson(test::generate(f.name, {}, 1).scene), stored) << path;
  }
}

}  // namespace
}  // namespace dash
