// KdTree (kd_neighbors.h): leaves of up to kLeafSize points split at the median of their widest
// coordinate; exact k-nearest and radius queries with plane pruning.
#include "engine/motion/kd_neighbors.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/core/check.h"

namespace dash {

namespace {

/// Heap order: the worst (largest distance, then latest insertion) on top.
bool worse(const KdTree::Found& a, const KdTree::Found& b) {
  return a.squared != b.squared ? a.squared < b.squared : a.seq < b.seq;
}

}  // namespace

KdTree::KdTree(unsigned int dimension) : dimension_(dimension) {
  DASH_DEMAND_MSG(dimension_ >= 1, "a k-d tree needs at least one coordinate");
  clear();
}

void KdTree::clear() {
  nodes_.assign(1, Node{});  // the root leaf grows as it fills: many roadmaps stay small
  size_ = 0;
}

KdTree::Node KdTree::newLeaf() const {
  Node node;
  node.q.reserve((kLeafSize + 1) * dimension_);
  node.ids.reserve(2 * (kLeafSize + 1));
  return node;
}

double KdTree::squared(const double* a, const double* b) const {
  double sum = 0.0;  // RealVectorStateSpace::distance's sum, in its order
  for (unsigned int i = 0; i < dimension_; ++i) {
    const double d = a[i] - b[i];
    sum += d * d;
  }
  return sum;
}

int KdTree::leafOf(const double* q) const {
  int n = 0;
  while (nodes_[static_cast<std::size_t>(n)].dim >= 0) {
    const Node& node = nodes_[static_cast<std::size_t>(n)];
    n = q[node.dim] < node.split ? node.left : node.right;
  }
  return n;
}

void KdTree::add(const double* q, std::uint64_t payload) {
  const int leaf = leafOf(q);
  Node& node = nodes_[static_cast<std::size_t>(leaf)];
  node.q.insert(node.q.end(), q, q + dimension_);
  node.ids.push_back(payload);
  node.ids.push_back(next_seq_++);
  ++size_;
  if (node.ids.size() > 2 * kLeafSize) splitLeaf(leaf);
}

void KdTree::splitLeaf(int leaf) {
  Node& node = nodes_[static_cast<std::size_t>(leaf)];
  const std::size_t n = node.ids.size() / 2;
  // The widest coordinate; all points equal along it (duplicates): the leaf stays a leaf.
  int dim = -1;
  double widest = 0.0;
  for (unsigned int d = 0; d < dimension_; ++d) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < n; ++i) {
      lo = std::min(lo, node.q[i * dimension_ + d]);
      hi = std::max(hi, node.q[i * dimension_ + d]);
    }
    if (hi - lo > widest) {
      widest = hi - lo;
      dim = static_cast<int>(d);
    }
  }
  if (dim < 0) return;
  std::vector<double> values(n);
  for (std::size_t i = 0; i < n; ++i) values[i] = node.q[i * dimension_ + static_cast<unsigned int>(dim)];
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(n / 2), values.end());
  double split = values[n / 2];
  // Points below the split go left: a split at the minimum would leave the left side empty.
  if (split == *std::min_element(values.begin(), values.end())) {
    split = std::numeric_limits<double>::infinity();
    for (const double v : values)
      if (v > values[n / 2]) split = std::min(split, v);
  }
  Node left = newLeaf(), right = newLeaf();
  for (std::size_t i = 0; i < n; ++i) {
    Node& side = node.q[i * dimension_ + static_cast<unsigned int>(dim)] < split ? left : right;
    side.q.insert(side.q.end(), node.q.begin() + static_cast<std::ptrdiff_t>(i * dimension_),
                  node.q.begin() + static_cast<std::ptrdiff_t>((i + 1) * dimension_));
    side.ids.push_back(node.ids[2 * i]);
    side.ids.push_back(node.ids[2 * i + 1]);
  }
  const int l = static_cast<int>(nodes_.size());
  nodes_.push_back(std::move(left));
  nodes_.push_back(std::move(right));
  Node& parent = nodes_[static_cast<std::size_t>(leaf)];  // push_back may have moved it
  parent.dim = dim;
  parent.split = split;
  parent.left = l;
  parent.right = l + 1;
  parent.q = {};
  parent.ids = {};
}

bool KdTree::remove(const double* q, std::uint64_t payload) {
  Node& node = nodes_[static_cast<std::size_t>(leafOf(q))];
  for (std::size_t i = 0; 2 * i < node.ids.size(); ++i) {
    if (node.ids[2 * i] != payload) continue;
    const std::size_t last = node.ids.size() / 2 - 1;
    std::copy_n(node.q.begin() + static_cast<std::ptrdiff_t>(last * dimension_), dimension_,
                node.q.begin() + static_cast<std::ptrdiff_t>(i * dimension_));
    node.q.resize(last * dimension_);
    node.ids[2 * i] = node.ids[2 * last];
    node.ids[2 * i + 1] = node.ids[2 * last + 1];
    node.ids.resize(2 * last);
    --size_;
    return true;
  }
  return false;
}

void KdTree::searchK(int n, const double* q, std::size_t k, std::vector<Found>& heap) const {
  const Node& node = nodes_[static_cast<std::size_t>(n)];
  if (node.dim < 0) {
    for (std::size_t i = 0; 2 * i < node.ids.size(); ++i) {
      const Found f{squared(q, node.q.data() + i * dimension_), node.ids[2 * i + 1], node.ids[2 * i]};
      if (heap.size() < k) {
        heap.push_back(f);
        std::push_heap(heap.begin(), heap.end(), worse);
      } else if (worse(f, heap.front())) {
        std::pop_heap(heap.begin(), heap.end(), worse);
        heap.back() = f;
        std::push_heap(heap.begin(), heap.end(), worse);
      }
    }
    return;
  }
  const double off = q[node.dim] - node.split;
  searchK(off < 0.0 ? node.left : node.right, q, k, heap);
  // The far side can hold a nearer point only within the plane's distance (ties included).
  if (heap.size() < k || off * off <= heap.front().squared) searchK(off < 0.0 ? node.right : node.left, q, k, heap);
}

void KdTree::nearestK(const double* q, std::size_t k, std::vector<Found>& out) const {
  out.clear();
  if (k == 0 || size_ == 0) return;
  searchK(0, q, k, out);
  std::sort_heap(out.begin(), out.end(), worse);
}

void KdTree::searchR(int n, const double* q, double radius, std::vector<Found>& out) const {
  const Node& node = nodes_[static_cast<std::size_t>(n)];
  if (node.dim < 0) {
    for (std::size_t i = 0; 2 * i < node.ids.size(); ++i) {
      const double s = squared(q, node.q.data() + i * dimension_);
      if (std::sqrt(s) <= radius) out.push_back({s, node.ids[2 * i + 1], node.ids[2 * i]});
    }
    return;
  }
  const double off = q[node.dim] - node.split;
  searchR(off < 0.0 ? node.left : node.right, q, radius, out);
  if (std::abs(off) <= radius) searchR(off < 0.0 ? node.right : node.left, q, radius, out);
}

void KdTree::nearestR(const double* q, double radius, std::vector<Found>& out) const {
  out.clear();
  if (size_ != 0) searchR(0, q, radius, out);
  std::sort(out.begin(), out.end(), worse);
}

void KdTree::list(std::vector<std::uint64_t>& out) const {
  out.clear();
  for (const Node& node : nodes_)
    if (node.dim < 0)
      for (std::size_t i = 0; i < node.ids.size(); i += 2) out.push_back(node.ids[i]);
}

}  // namespace dash
