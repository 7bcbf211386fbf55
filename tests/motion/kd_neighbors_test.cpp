// The roadmaps' k-d tree (engine/motion/kd_neighbors.h) answers as an exact search does: the k nearest
// and the points within a radius, nearest first and equal distances in insertion order, through
// additions, removals, duplicates and leaf splits; and as og::LazyPRM's structure it keeps OMPL's
// seed sequence where GNAT left it.
#include <gtest/gtest.h>
#include <ompl/datastructures/NearestNeighborsGNATNoThreadSafety.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "engine/core/forked_run.h"
#include "engine/motion/kd_neighbors.h"

namespace dash {
namespace {

struct Point {
  std::vector<double> q;
  std::uint64_t id;
  std::uint64_t seq;
};

double squared(const std::vector<double>& a, const double* b) {
  double s = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) s += (a[i] - b[i]) * (a[i] - b[i]);
  return s;
}

/// The exact answer by sorting every point: (squared distance, insertion order).
std::vector<std::uint64_t> bruteK(const std::vector<Point>& points, const double* q, std::size_t k) {
  std::vector<std::pair<std::pair<double, std::uint64_t>, std::uint64_t>> all;
  for (const Point& p : points) all.push_back({{squared(p.q, q), p.seq}, p.id});
  std::sort(all.begin(), all.end());
  std::vector<std::uint64_t> out;
  for (std::size_t i = 0; i < std::min(k, all.size()); ++i) out.push_back(all[i].second);
  return out;
}

std::vector<std::uint64_t> ids(const std::vector<KdTree::Found>& found) {
  std::vector<std::uint64_t> out;
  for (const KdTree::Found& f : found) out.push_back(f.payload);
  return out;
}

TEST(KdTree, KNearestAndRadiusAnswersEqualAnExactSearchThroughAdditionsRemovalsAndDuplicates) {
  constexpr unsigned int kDim = 6;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-3.14, 3.14);
  KdTree tree(kDim);
  std::vector<Point> points;
  std::uint64_t seq = 0;
  for (int step = 0; step < 3000; ++step) {
    Point p{std::vector<double>(kDim), static_cast<std::uint64_t>(step), seq++};
    // Every 50th point repeats an earlier one (equal distances), every 7th lies on a grid (equal coordinates).
    if (step % 50 == 49) p.q = points[static_cast<std::size_t>(step) % points.size()].q;
    else for (double& x : p.q) x = step % 7 == 0 ? std::round(u(rng)) : u(rng);
    tree.add(p.q.data(), p.id);
    points.push_back(p);
    if (step % 5 == 4) {  // remove a point now and then
      const std::size_t victim = static_cast<std::size_t>(rng() % points.size());
      ASSERT_TRUE(tree.remove(points[victim].q.data(), points[victim].id));
      points.erase(points.begin() + static_cast<std::ptrdiff_t>(victim));
    }
    if (step % 37 != 0) continue;
    std::vector<double> q(kDim);
    for (double& x : q) x = u(rng);
    if (step % 74 == 0) q = points[0].q;  // a query at a stored point
    std::vector<KdTree::Found> found;
    for (const std::size_t k : {std::size_t{1}, std::size_t{10}, points.size() + 3}) {
      tree.nearestK(q.data(), k, found);
      ASSERT_EQ(ids(found), bruteK(points, q.data(), k)) << "step " << step << " k " << k;
    }
    const double radius = 1.5;
    tree.nearestR(q.data(), radius, found);
    std::vector<std::uint64_t> within;
    for (const std::uint64_t id : bruteK(points, q.data(), points.size()))
      for (const Point& p : points)
        if (p.id == id && std::sqrt(squared(p.q, q.data())) <= radius) within.push_back(id);
    ASSERT_EQ(ids(found), within) << "step " << step;
  }
  EXPECT_EQ(tree.size(), points.size());
  std::vector<std::uint64_t> listed;
  tree.list(listed);
  EXPECT_EQ(listed.size(), points.size());
  const double nowhere[kDim] = {9, 9, 9, 9, 9, 9};
  EXPECT_FALSE(tree.remove(nowhere, 12345));
}

TEST(KdTree, MoreEqualPointsThanALeafHoldsStayExactAndRemovable) {
  // No split separates equal points: their leaf grows past its reserved size and still answers exactly.
  constexpr unsigned int kDim = 3;
  KdTree tree(kDim);
  std::vector<Point> points;
  for (std::uint64_t i = 0; i < 60; ++i) {
    Point p{i % 3 == 0 ? std::vector<double>{0.1 * static_cast<double>(i), 0.2, -0.3} : std::vector<double>{1, 2, 3}, i, i};
    tree.add(p.q.data(), p.id);
    points.push_back(p);
  }
  const double q[kDim] = {1, 2, 3.5};
  std::vector<KdTree::Found> found;
  tree.nearestK(q, 50, found);
  EXPECT_EQ(ids(found), bruteK(points, q, 50));
  for (std::size_t i = 0; i < points.size(); i += 2) ASSERT_TRUE(tree.remove(points[i].q.data(), points[i].id)) << i;
  std::vector<Point> left;
  for (std::size_t i = 1; i < points.size(); i += 2) left.push_back(points[i]);
  tree.nearestK(q, 100, found);
  EXPECT_EQ(ids(found), bruteK(left, q, 100));
  EXPECT_EQ(tree.size(), left.size());
}

TEST(KdNeighbors, TakesOneSeedOfOmplsSequenceAsGnatDid) {
  // OMPL seeds each new generator with the next number of one process-wide sequence, and the roadmaps'
  // samplers are made after the neighbour structure: the generator made next must get the seed it got
  // after og::LazyPRM's default GNAT. Both forked from this state; without the tree's unused
  // generator the seeds differ.
  const ompl::RNG started;  // OMPL's sequence starts here, once: both children inherit its state
  const ForkedRun with_gnat = runForked([] {
    const ompl::NearestNeighborsGNATNoThreadSafety<void*> gnat;
    return std::to_string(ompl::RNG().getLocalSeed());
  });
  const ForkedRun with_tree = runForked([] {
    const KdNeighbors<void*> tree(6, [](void* const&) -> const double* { return nullptr; });
    return std::to_string(ompl::RNG().getLocalSeed());
  });
  ASSERT_TRUE(with_gnat.finished && with_tree.finished);
  EXPECT_EQ(with_tree.output, with_gnat.output);
  const ForkedRun with_nothing = runForked([] { return std::to_string(ompl::RNG().getLocalSeed()); });
  EXPECT_NE(with_nothing.output, with_gnat.output) << "the check cannot tell one generator from none";
}

}  // namespace
}  // namespace dash
