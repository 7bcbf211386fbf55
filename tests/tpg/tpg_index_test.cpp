// The box index of the graph builder (engine/tpg/tpg_index.h): the latest piece before a given one
// whose box comes within a margin of a query box, and every such piece, agree with a scan of all.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "engine/tpg/tpg_index.h"

namespace dash::tpg::detail {
namespace {

std::vector<Aabb> randomBoxes(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> where(0.0, 1.0), size(0.0, 0.3);  // dense: many near
  std::vector<Aabb> boxes;
  for (int k = 0; k < n; ++k) {
    const Vec3 lo(where(rng), where(rng), where(rng));
    if (k % 17 == 5) {
      boxes.emplace_back();  // empty: never near
      boxes.back().setEmpty();
      continue;
    }
    boxes.emplace_back(lo, lo + Vec3(size(rng), size(rng), size(rng)));
  }
  return boxes;
}

bool nearBox(const Aabb& box, const Aabb& query, double margin) {
  return !box.isEmpty() && box.exteriorDistance(query) <= margin;
}

TEST(TpgBoxIndex, LatestNearAndNearAgreeWithAScanOfEveryBox) {
  std::mt19937 rng(7);
  for (int n : {0, 1, 2, 5, 64, 100, 333}) {
    const std::vector<Aabb> boxes = randomBoxes(rng, n);
    const BoxIndex index(boxes);
    ASSERT_EQ(index.size(), n);
    std::uniform_int_distribution<int> pick(0, n);
    for (int q = 0; q < 200; ++q) {
      const Aabb query = randomBoxes(rng, 1).front();
      const double margin = q % 3 == 0 ? 0.0 : 0.05;
      const int lo = pick(rng), hi = pick(rng);
      int expected = -1;
      for (int k = lo; k < hi; ++k) {
        if (nearBox(boxes[static_cast<std::size_t>(k)], query, margin)) expected = k;
      }
      EXPECT_EQ(index.latestNear(query, margin, lo, hi), expected) << "n " << n << " [" << lo << ", " << hi << ")";
      std::vector<int> all, scanned;
      index.near(query, margin, all);
      for (int k = 0; k < n; ++k) {
        if (nearBox(boxes[static_cast<std::size_t>(k)], query, margin)) scanned.push_back(k);
      }
      EXPECT_EQ(all, scanned) << "n " << n;
    }
  }
}

}  // namespace
}  // namespace dash::tpg::detail
