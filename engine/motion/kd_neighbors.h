#pragma once
// The roadmaps' nearest-neighbour structure (issue 38): an exact k-d tree over joint vectors, in place of
// OMPL's default GNAT. On sorting 16/64 the k-nearest queries of new milestones (og::LazyPRM's
// addMilestone) were 40 % of a run on one thread, most of it GNAT's distance calls, each reading three
// scattered objects (vertex, OMPL state, value array). Here a leaf holds up to kLeafSize points with
// their coordinates side by side, queries compare squared distances, and whole subtrees are pruned by
// the distance to a splitting plane.
//
// The answers are GNAT's: the exact k nearest (or all within a radius), nearest first. Equal distances
// (only for equal configurations, which the roadmap avoids) are ordered by insertion. The tree makes no
// random draws; it constructs one ompl::RNG that it never uses, where GNAT's pivot selector constructed
// its own, so that every generator made after it gets the seed it got with GNAT (OMPL seeds each new
// generator from one process-wide sequence) and a run samples what it sampled before.
// Include only from .cpp files that use OMPL.
#include <ompl/datastructures/NearestNeighbors.h>
#include <ompl/util/RandomNumbers.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <vector>

namespace dash {

/// The k-d tree proper, over points of `dimension` doubles with an opaque 64-bit payload.
class KdTree {
 public:
  static constexpr std::size_t kLeafSize = 16;
  struct Found {
    double squared;
    std::uint64_t seq;  ///< insertion order: the tie-break
    std::uint64_t payload;
  };

  explicit KdTree(unsigned int dimension);
  void clear();
  void add(const double* q, std::uint64_t payload);
  /// Removes the point with this payload at `q` (its coordinates when added); false if absent.
  bool remove(const double* q, std::uint64_t payload);
  /// The k nearest to q, nearest first.
  void nearestK(const double* q, std::size_t k, std::vector<Found>& out) const;
  /// Every point within `radius` of q (the distance as sqrt of the sum, as OMPL computes it), nearest first.
  void nearestR(const double* q, double radius, std::vector<Found>& out) const;
  std::size_t size() const { return size_; }
  void list(std::vector<std::uint64_t>& out) const;

 private:
  struct Node {
    int dim = -1;  ///< -1: a leaf
    double split = 0.0;
    int left = -1, right = -1;
    std::vector<double> q;  ///< leaf: the points' coordinates, one after another
    std::vector<std::uint64_t> ids;  ///< leaf: per point its payload, then its insertion number
  };
  /// A leaf made by a split (half full or more), its storage reserved for the most points it holds
  /// before it splits in turn (grown by doubling, the leaves took 80 of the 353 MB of sorting 16/64's
  /// peak heap). Equal points beyond that, which no split separates, still fit: the vectors grow.
  Node newLeaf() const;
  int leafOf(const double* q) const;
  void splitLeaf(int leaf);
  double squared(const double* a, const double* b) const;
  void searchK(int node, const double* q, std::size_t k, std::vector<Found>& heap) const;
  void searchR(int node, const double* q, double radius, std::vector<Found>& out) const;

  unsigned int dimension_;
  std::vector<Node> nodes_;
  std::size_t size_ = 0;
  std::uint64_t next_seq_ = 0;
};

/// og::LazyPRM's NearestNeighbors<Vertex> over KdTree; `coordinates` gives a vertex's joint vector.
template <class Vertex>
class KdNeighbors final : public ompl::NearestNeighbors<Vertex> {
 public:
  using Coordinates = std::function<const double*(const Vertex&)>;
  KdNeighbors(unsigned int dimension, Coordinates coordinates)
      : tree_(dimension), coordinates_(std::move(coordinates)) {}

  bool reportsSortedResults() const override { return true; }
  void clear() override { tree_.clear(); }
  void add(const Vertex& v) override { tree_.add(coordinates_(v), key(v)); }
  void add(const std::vector<Vertex>& vs) override {
    for (const Vertex& v : vs) add(v);
  }
  bool remove(const Vertex& v) override { return tree_.remove(coordinates_(v), key(v)); }
  Vertex nearest(const Vertex& v) const override {
    tree_.nearestK(coordinates_(v), 1, found_);
    return found_.empty() ? Vertex() : vertex(found_[0].payload);
  }
  void nearestK(const Vertex& v, std::size_t k, std::vector<Vertex>& out) const override {
    tree_.nearestK(coordinates_(v), k, found_);
    vertices(out);
  }
  void nearestR(const Vertex& v, double radius, std::vector<Vertex>& out) const override {
    tree_.nearestR(coordinates_(v), radius, found_);
    vertices(out);
  }
  std::size_t size() const override { return tree_.size(); }
  void list(std::vector<Vertex>& out) const override {
    std::vector<std::uint64_t> all;
    tree_.list(all);
    out.clear();
    for (const std::uint64_t p : all) out.push_back(vertex(p));
  }

 private:
  static_assert(sizeof(Vertex) <= sizeof(std::uint64_t), "a vertex must fit the payload");
  static std::uint64_t key(const Vertex& v) {
    std::uint64_t k = 0;
    std::memcpy(&k, &v, sizeof v);
    return k;
  }
  static Vertex vertex(std::uint64_t k) {
    Vertex v;
    std::memcpy(&v, &k, sizeof v);
    return v;
  }
  void vertices(std::vector<Vertex>& out) const {
    out.resize(found_.size());
    for (std::size_t i = 0; i < found_.size(); ++i) out[i] = vertex(found_[i].payload);
  }

  KdTree tree_;
  Coordinates coordinates_;
  ompl::RNG gnat_seed_;  ///< never drawn from: see the header comment
  mutable std::vector<KdTree::Found> found_;
};

}  // namespace dash
