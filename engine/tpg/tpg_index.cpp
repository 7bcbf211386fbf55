#include "engine/tpg/tpg_index.h"

#include <algorithm>

namespace dash::tpg::detail {

namespace {
inline std::size_t at(int i) { return static_cast<std::size_t>(i); }
}  // namespace

BoxIndex::BoxIndex(const std::vector<Aabb>& boxes) : n_(static_cast<int>(boxes.size())) {
  while (leaves_ < n_) leaves_ *= 2;
  Aabb empty;
  empty.setEmpty();
  tree_.assign(at(2 * leaves_), empty);
  for (int k = 0; k < n_; ++k) tree_[at(leaves_ + k)] = boxes[at(k)];
  for (int i = leaves_ - 1; i >= 1; --i) {
    tree_[at(i)] = tree_[at(2 * i)];
    if (!tree_[at(2 * i + 1)].isEmpty()) tree_[at(i)].extend(tree_[at(2 * i + 1)]);
  }
}

bool BoxIndex::far(int node, const Aabb& query, double margin) const {
  const Aabb& box = tree_[at(node)];
  return box.isEmpty() || box.exteriorDistance(query) > margin;
}

int BoxIndex::latest(int node, int node_lo, int node_hi, const Aabb& query, double margin, int lo, int hi) const {
  if (node_hi <= lo || node_lo >= hi || far(node, query, margin)) return -1;
  if (node >= leaves_) return node - leaves_;
  const int mid = (node_lo + node_hi) / 2;
  const int right = latest(2 * node + 1, mid, node_hi, query, margin, lo, hi);
  return right >= 0 ? right : latest(2 * node, node_lo, mid, query, margin, lo, hi);
}

int BoxIndex::latestNear(const Aabb& query, double margin, int lo, int hi) const {
  if (n_ == 0 || query.isEmpty()) return -1;
  return latest(1, 0, leaves_, query, margin, std::max(lo, 0), std::min(hi, n_));
}

void BoxIndex::collect(int node, int node_lo, int node_hi, const Aabb& query, double margin,
                       std::vector<int>& out) const {
  if (node_lo >= n_ || far(node, query, margin)) return;
  if (node >= leaves_) {
    out.push_back(node - leaves_);
    return;
  }
  const int mid = (node_lo + node_hi) / 2;
  collect(2 * node, node_lo, mid, query, margin, out);
  collect(2 * node + 1, mid, node_hi, query, margin, out);
}

void BoxIndex::near(const Aabb& query, double margin, std::vector<int>& out) const {
  if (n_ == 0 || query.isEmpty()) return;
  collect(1, 0, leaves_, query, margin, out);
}

}  // namespace dash::tpg::detail
