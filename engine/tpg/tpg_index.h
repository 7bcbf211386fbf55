#pragma once
// Internal to engine/tpg: one arm's pieces in time order, indexed by their swept boxes (a segment
// tree of union boxes over the time order), so the builder finds the pieces that can come near a
// given box without scanning an arm's whole history: "the latest piece before this one that comes
// within the clearance" costs a walk down the tree per candidate, not a test of every earlier piece.
#include <vector>

#include "engine/collision/collision_world.h"

namespace dash::tpg::detail {

class BoxIndex {
 public:
  /// boxes[k]: piece k's box (empty boxes never come near anything).
  explicit BoxIndex(const std::vector<Aabb>& boxes);

  /// The largest k in [lo, hi) whose box comes within `margin` of `query`; -1 if none.
  int latestNear(const Aabb& query, double margin, int lo, int hi) const;
  /// Every k whose box comes within `margin` of `query`, ascending (appended to `out`).
  void near(const Aabb& query, double margin, std::vector<int>& out) const;
  int size() const { return n_; }

 private:
  bool far(int node, const Aabb& query, double margin) const;
  int latest(int node, int node_lo, int node_hi, const Aabb& query, double margin, int lo, int hi) const;
  void collect(int node, int node_lo, int node_hi, const Aabb& query, double margin, std::vector<int>& out) const;

  int n_ = 0;
  int leaves_ = 1;           ///< a power of two >= n_
  std::vector<Aabb> tree_;   ///< 1-based heap: node i has children 2i, 2i+1; leaf k at leaves_ + k
};

}  // namespace dash::tpg::detail
