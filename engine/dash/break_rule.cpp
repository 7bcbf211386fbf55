#include "engine/dash/break_rule.h"

#include <algorithm>

#include "engine/core/check.h"

namespace dash {

BreakRule::BreakRule(int robot_count, BreakRuleParams params, std::uint64_t seed)
    : params_(params), rng_(seed), growths_(static_cast<std::size_t>(std::max(robot_count, 0)), 0) {
  DASH_DEMAND(robot_count >= 0);
}

BreakRule::Choice BreakRule::decide(const MotionConflict& conflict) {
  Choice choice;
  std::vector<int> growable;
  for (int r : conflict.robots) {
    DASH_DEMAND(r >= 0 && r < static_cast<int>(growths_.size()));
    if (growths(r) < params_.max_roadmap_growths && std::find(growable.begin(), growable.end(), r) == growable.end())
      growable.push_back(r);
  }
  const bool can_branch = !conflict.arcs.empty();
  bool grow = false;
  if (!can_branch) {
    grow = !growable.empty();  // nothing to forbid: growing is all that can change the next query
  } else if (!growable.empty() && conflict.kind != MotionConflict::Kind::kTransition) {
    // The draw happens only when there is a choice: a forced choice leaves the stream alone.
    grow = rng_.uniform01() < params_.grow_roadmap_probability;
  }
  if (grow) {
    choice.decision = Decision::kGrowRoadmaps;
    choice.robots = std::move(growable);
    for (int r : choice.robots) ++growths_[static_cast<std::size_t>(r)];
    ++roadmap_decisions_;
  } else if (can_branch) {
    choice.decision = Decision::kGrowTree;
    ++tree_decisions_;
  }
  return choice;
}

const char* toString(BreakRule::Decision d) {
  switch (d) {
    case BreakRule::Decision::kGrowRoadmaps: return "grow-roadmaps";
    case BreakRule::Decision::kGrowTree: return "grow-tree";
    case BreakRule::Decision::kDeadNode: return "dead-node";
  }
  return "?";
}

}  // namespace dash
