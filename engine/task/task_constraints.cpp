#include "engine/task/task_constraints.h"

namespace dash {

const char* constraintKindName(TaskConstraint::Kind kind) {
  switch (kind) {
    case TaskConstraint::Kind::kFrontier: return "frontier";
    case TaskConstraint::Kind::kHistory: return "history";
    case TaskConstraint::Kind::kInteraction: return "interaction";
  }
  return "?";
}

bool TaskConstraint::sameAs(const TaskConstraint& o) const {
  if (kind != o.kind) return false;
  if (kind == Kind::kInteraction)
    return arc == o.arc && giver == o.giver && receiver == o.receiver && giver_grasp == o.giver_grasp &&
           receiver_grasp == o.receiver_grasp;
  return pre == o.pre && post == o.post;
}

bool TaskConstraintSet::add(const TaskConstraint& c) {
  for (const auto& existing : constraints_)
    if (existing.sameAs(c)) return false;
  const int index = static_cast<int>(constraints_.size());
  constraints_.push_back(c);
  if (c.kind == TaskConstraint::Kind::kInteraction) {
    interactions_.push_back(index);
  } else {
    by_post_[c.post.value()].push_back(index);
    by_pre_[c.pre.value()].push_back(index);
  }
  return true;
}

std::vector<TaskConstraint> TaskConstraintSet::removeWhere(bool (*remove)(const TaskConstraint&)) {
  std::vector<TaskConstraint> removed, kept;
  for (const TaskConstraint& c : constraints_) (remove(c) ? removed : kept).push_back(c);
  if (removed.empty()) return removed;
  constraints_.clear();
  by_post_.clear();
  by_pre_.clear();
  interactions_.clear();
  for (const TaskConstraint& c : kept) add(c);
  return removed;
}

std::vector<TaskConstraint> TaskConstraintSet::removeTemporary() {
  return removeWhere([](const TaskConstraint& c) { return c.temporary; });
}

std::vector<TaskConstraint> TaskConstraintSet::removeAll() {
  return removeWhere([](const TaskConstraint&) { return true; });
}

std::vector<TaskConstraint> TaskConstraintSet::expireTemporary() {
  for (TaskConstraint& c : constraints_)
    if (c.temporary) --c.queries;
  return removeWhere([](const TaskConstraint& c) { return c.temporary && c.queries <= 0; });
}

bool TaskConstraintSet::forbidsInteraction(HyperarcId id, const TaskArc& arc) const {
  for (int i : interactions_) {
    const TaskConstraint& c = constraints_[i];
    if (c.arc.valid()) {
      if (c.arc == id) return true;
      continue;
    }
    if (arc.type == TaskArcType::kHandover && c.giver == arc.robot && c.receiver == arc.robot2 && c.giver_grasp == arc.grasp &&
        c.receiver_grasp == arc.grasp2)
      return true;
  }
  return false;
}

HyperarcFilter TaskConstraintSet::filter(const TaskGraph& graph) const {
  return [this, &graph](const HyperpathState& state, HyperarcId a) {
    if (!interactions_.empty() && forbidsInteraction(a, graph.property(a))) return false;
    for (VertexId pre : graph.head(a)) {
      auto it = by_pre_.find(pre.value());
      if (it == by_pre_.end()) continue;
      for (int i : it->second) {
        const TaskConstraint& c = constraints_[i];
        if (c.kind == TaskConstraint::Kind::kHistory && c.post_required && !state.inHistory(c.post)) return false;
      }
    }
    for (VertexId post : graph.head(a)) {
      auto it = by_post_.find(post.value());
      if (it == by_post_.end()) continue;
      for (int i : it->second) {
        const TaskConstraint& c = constraints_[i];
        if (c.kind == TaskConstraint::Kind::kFrontier && state.inFrontier(c.pre)) return false;
        if (c.kind == TaskConstraint::Kind::kHistory && state.inHistory(c.pre)) return false;
      }
    }
    return true;
  };
}

bool TaskConstraintSet::historyRelevant(VertexId v) const {
  if (auto it = by_pre_.find(v.value()); it != by_pre_.end())
    for (int i : it->second)
      if (constraints_[i].kind == TaskConstraint::Kind::kHistory) return true;
  // The required v_post of a history constraint decides what may follow (filter()).
  if (auto it = by_post_.find(v.value()); it != by_post_.end())
    for (int i : it->second)
      if (constraints_[i].kind == TaskConstraint::Kind::kHistory && constraints_[i].post_required) return true;
  return false;
}

std::vector<const TaskConstraint*> TaskConstraintSet::constraintsOnPost(VertexId post) const {
  std::vector<const TaskConstraint*> out;
  if (auto it = by_post_.find(post.value()); it != by_post_.end())
    for (int i : it->second) out.push_back(&constraints_[i]);
  return out;
}

std::vector<const TaskConstraint*> TaskConstraintSet::constraintsOnPre(VertexId pre) const {
  std::vector<const TaskConstraint*> out;
  if (auto it = by_pre_.find(pre.value()); it != by_pre_.end())
    for (int i : it->second) out.push_back(&constraints_[i]);
  return out;
}

}  // namespace dash
