#pragma once
// Task constraints (paper, "Query (Task-extended Hypergraph)"): C_T = C_h ∪ C_f over pairs
// (v_pre, v_post). A frontier constraint forbids expanding a hyperarc with v_post in its head while
// v_pre is on the frontier; a history constraint forbids it once v_pre has appeared in the history.
// Constraints chain: a v_post may be the v_pre of another. Interaction constraints forbid a transition
// outright (a handover whose configurations are never collision-free, e.g. through a wall).
#include <string>
#include <unordered_map>
#include <vector>

#include "engine/hypergraph/hyperpath_search.h"
#include "engine/task/task_hypergraph.h"

namespace dash {

struct TaskConstraint {
  enum class Kind { kFrontier, kHistory, kInteraction };
  Kind kind = Kind::kFrontier;
  VertexId pre;   ///< frontier/history
  VertexId post;  ///< frontier/history
  /// Interaction: forbids one hyperarc (when valid), or else every handover from `giver` to
  /// `receiver` with these grasp classes.
  HyperarcId arc;
  int giver = -1;
  int receiver = -1;
  GraspClass giver_grasp = GraspClass::kTop;
  GraspClass receiver_grasp = GraspClass::kTop;
  std::string cause;  ///< the conflict that produced it, for logs
  /// Fed back from the motion layer: holds for `queries` task queries only (the paper does not remove
  /// a hyperarc for ever because one motion failed).
  bool temporary = false;
  int queries = 1;
  /// Fed back from the motion layer or conflict resolution (a motion constraint in the event stream).
  bool from_motion = false;
  /// History: v_post must be in every complete plan (an object at its final goal). Then v_pre may
  /// not appear before v_post either: afterwards v_post could never be reached (a dead end pruned
  /// early instead of found by backtracking).
  bool post_required = false;

  bool sameAs(const TaskConstraint& o) const;
};
const char* constraintKindName(TaskConstraint::Kind kind);

class TaskConstraintSet {
 public:
  /// Adds a constraint unless an equal one exists; returns whether it was new.
  bool add(const TaskConstraint& c);
  const std::vector<TaskConstraint>& all() const { return constraints_; }
  /// Removes the temporary constraints; returns them.
  std::vector<TaskConstraint> removeTemporary();
  /// Removes every constraint; returns them.
  std::vector<TaskConstraint> removeAll();
  /// One task query has been answered: temporary constraints count it down; those that reach zero
  /// are removed and returned.
  std::vector<TaskConstraint> expireTemporary();
  bool empty() const { return constraints_.empty(); }
  std::size_t size() const { return constraints_.size(); }

  /// The search hook: may this hyperarc be expanded from this state?
  HyperarcFilter filter(const TaskGraph& graph) const;
  /// Vertices that appear as v_pre of history constraints.
  bool historyRelevant(VertexId v) const;
  /// Constraints whose v_post is `post` (frontier and history).
  std::vector<const TaskConstraint*> constraintsOnPost(VertexId post) const;
  /// Constraints whose v_pre is `pre`.
  std::vector<const TaskConstraint*> constraintsOnPre(VertexId pre) const;
  bool forbidsInteraction(HyperarcId id, const TaskArc& arc) const;
  /// Calls f(constraint) for each frontier/history constraint whose v_pre is `pre` (no allocation).
  template <class F>
  void forEachOnPre(VertexId pre, F&& f) const {
    if (auto it = by_pre_.find(pre.value()); it != by_pre_.end())
      for (int i : it->second) f(constraints_[i]);
  }

 private:
  /// Removes the constraints `remove` selects (rebuilding the indices); returns them.
  std::vector<TaskConstraint> removeWhere(bool (*remove)(const TaskConstraint&));
  std::vector<TaskConstraint> constraints_;
  std::unordered_map<std::uint32_t, std::vector<int>> by_post_;
  std::unordered_map<std::uint32_t, std::vector<int>> by_pre_;
  std::vector<int> interactions_;
};

}  // namespace dash
