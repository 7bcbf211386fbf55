#pragma once
// CBS-MP's probabilistic break rule (Solis, Motes, Sandström, Amato, "Representation-optimal
// multi-robot motion planning using conflict-based search", RA-L 2021), as DaSH uses it (Lazy-DaSH
// paper, "Method Descriptions": the rule "determine[s] whether to continue expanding the constraint
// tree or to expand the roadmaps before restarting the query"). A conflict that conflict resolution
// could not repair either
//  - grows the roadmaps of the robots involved, and the same constraint tree node is queried again
//    (the conflict may vanish with a better path), or
//  - grows the constraint tree: one child per motion hyperarc involved, each forbidding it.
// The choice is random, with probability `grow_roadmap_probability` for the roadmaps, as long as a
// robot involved has growth left. A transition conflict always grows the tree: more roadmap samples
// cannot move a sampled transition configuration. A conflict with no hyperarc to forbid can only grow
// the roadmaps; with nothing to grow either, its node is dead.
#include <cstdint>
#include <limits>
#include <vector>

#include "engine/core/rng.h"
#include "engine/dash/resting_conflicts.h"

namespace dash {

struct BreakRuleParams {
  double grow_roadmap_probability = 0.3;  ///< chance to grow the roadmaps rather than the tree
  /// Per robot: then only the tree grows. Unlimited by default: the roadmaps keep growing until the
  /// deadline, as PRM's probabilistic completeness asks.
  int max_roadmap_growths = std::numeric_limits<int>::max();
};

class BreakRule {
 public:
  enum class Decision { kGrowRoadmaps, kGrowTree, kDeadNode };
  struct Choice {
    Decision decision = Decision::kDeadNode;
    std::vector<int> robots;  ///< kGrowRoadmaps: the robots whose roadmaps grow
  };

  BreakRule(int robot_count, BreakRuleParams params, std::uint64_t seed);

  /// Decides for one conflict; a roadmap decision counts against each robot's growth budget.
  Choice decide(const MotionConflict& conflict);

  int growths(int robot) const { return growths_[static_cast<std::size_t>(robot)]; }
  int roadmapDecisions() const { return roadmap_decisions_; }
  int treeDecisions() const { return tree_decisions_; }

 private:
  BreakRuleParams params_;
  Rng rng_;
  std::vector<int> growths_;
  int roadmap_decisions_ = 0;
  int tree_decisions_ = 0;
};

const char* toString(BreakRule::Decision d);

}  // namespace dash
