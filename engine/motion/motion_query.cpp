// MotionLayer's motion query (paper, "Query (Motion-extended Hypergraph)"): a search over H_M guided by
// the task plan. In schedule order each robot's next visit needs a move from where the robot's previous
// retreat ended to an approach start; the query validates that move lazily (the straight segment first,
// then the robot's Lazy-PRM roadmap, in the motion context of that moment: what rests where, what the
// robot holds, the regions of the motion constraints on its history) and takes the visit's hyperarcs
// (transit, approach; the step's transition once all its robots arrived; the retreats). When no move is
// found, H_M grows (paper, "Theoretical Properties": local refinement, then global sampling): a farther
// approach start along the same axis is tried, then the query backtracks to the robot's previous visit
// and takes its farther retreat end instead, and finally RRT-Connect grows trees from both ends. Only
// that robot's previous visit can change where it starts, so the backtrack jumps there directly; the
// visits of other robots in between stay as they are. Every hyperarc taken, on a branch later left
// too, is one extended hyperarc of H_ME.
#include <optional>
#include <utility>

#include "engine/motion/motion_anchors.h"

namespace dash {

struct MotionQuery {
  MotionLayer& layer;
  MotionAnchors& h;
  const TaskPlan& plan;
  const Deadline& deadline;
  const Scene& scene;
  const TaskSpace* space;
  lazy::MotionHypergraph& graph = layer.graph_;
  MotionLayerResult result;
  std::vector<int> pre_choice, post_choice;  ///< per visit
  std::vector<std::vector<JointVector>> transit;  ///< per visit: the validated move to its approach start
  std::vector<VertexId> at;  ///< per robot: where its branch stands (H_M vertex)
  /// Hyperarcs taken on the branch that goes on (the hyperpath once the sink is reached); a retreat
  /// the query backtracked from is counted in H_ME only.
  std::size_t hyperpath = 0;

  MotionLayerResult run();
  /// Visit i's transit and approach found and taken; false when it stopped `result`.
  bool reach(int i);
  /// The move to approach start j of visit i from where the robot stands, validated and taken.
  bool tryApproach(int i, std::size_t j, bool trees);
  /// Local refinement: a farther approach start for visit i and a farther retreat end for its
  /// robot's previous visit, added to H_M (booked as motion construction).
  void refine(int i);
  /// The robot of visit i takes its retreat end `post_choice[i]`.
  void takeRetreat(int i);
  /// Visit i's validated move `arc` (none: the robot is already there) and its approach from start j.
  void takeTransit(int i, std::size_t j, std::optional<HyperarcId> arc, const std::vector<JointVector>& path);
  /// Where visit i's robot starts from: its previous visit's chosen retreat end, or home.
  const JointVector& from(int i) const;
  /// result as failed (or timed out) at visit i, with why.
  void fail(int i);
  /// The result's per-robot plans from the chosen branch.
  void collect();
};

const JointVector& MotionQuery::from(int i) const {
  const VisitAnchors& v = h.visits[i];
  return v.previous < 0 ? scene.robots[v.robot].home : h.visits[v.previous].post[post_choice[v.previous]];
}

MotionLayerResult MotionQuery::run() {
  const std::size_t n = h.visits.size();
  pre_choice.assign(n, 0);
  post_choice.assign(n, 0);
  transit.assign(n, {});
  at = h.home;
  result.robots.resize(scene.robots.size());
  graph.beginQuery();
  graph.take(h.source);
  ++hyperpath;
  for (std::size_t k = 0; k < h.step_visits.size(); ++k) {
    for (int i : h.step_visits[k])
      if (!reach(i)) return std::move(result);
    graph.take(h.transition[k]);
    ++hyperpath;
    for (int i : h.step_visits[k]) takeRetreat(i);
  }
  for (std::size_t i = 0; i < n; ++i)
    if (h.visits[i].home && !reach(static_cast<int>(i))) return std::move(result);
  std::vector<VertexId> ends = at;
  ends.insert(ends.end(), h.end_items.begin(), h.end_items.end());
  graph.take(graph.sink(ends));
  ++hyperpath;
  result.hyperpath_hyperarcs = hyperpath;
  layer.emitter_->counter("roadmap_vertices", static_cast<std::int64_t>(layer.roadmapVertices()));
  layer.emitter_->counter("roadmap_edges", static_cast<std::int64_t>(layer.roadmapEdges()));
  collect();
  result.status = MotionStatus::kOk;
  return std::move(result);
}

bool MotionQuery::reach(int i) {
  if (deadline.expired()) {
    result.status = MotionStatus::kTimeout;
    return false;
  }
  VisitAnchors& v = h.visits[i];
  if (tryApproach(i, 0, false)) return true;
  if (deadline.expired()) {
    fail(i);
    return false;
  }
  refine(i);
  for (std::size_t j = 1; j < v.pre.size(); ++j)
    if (tryApproach(i, j, false)) return true;
  // Backtrack: the robot's previous visit takes its farther retreat end, and this visit is tried again
  // from there (farthest approach start first: out of a cubby on both sides).
  const int p = v.previous;
  if (p >= 0 && post_choice[p] + 1 < static_cast<int>(h.visits[p].post.size()) && !deadline.expired()) {
    const VisitAnchors& prev = h.visits[p];
    if (prev.post_vertex[post_choice[p]] != prev.after_q) --hyperpath;  // that retreat stays in H_ME only
    ++post_choice[p];
    ++result.backtracks;
    layer.emitter_->counter("motion_query_backtracks", ++layer.query_backtracks_);
    takeRetreat(p);
    for (std::size_t j = v.pre.size(); j-- > 0;)
      if (tryApproach(i, j, false)) return true;
  }
  // Global sampling: trees grown from both ends of the last pair.
  if (layer.params_.global_sampling && !deadline.expired() && tryApproach(i, v.pre.size() - 1, true)) return true;
  fail(i);
  return false;
}

bool MotionQuery::tryApproach(int i, std::size_t j, bool trees) {
  VisitAnchors& v = h.visits[i];
  // The search expands the move (an extended hyperarc with its path not yet validated), then validates
  // it; a move that fails validation stays in H_ME as a dead branch.
  const auto arc = graph.move(at[v.robot], v.pre_vertex[j], {from(i), v.pre[j]}, false);
  if (arc) graph.take(*arc);
  const auto path = trees ? layer.roadmap(v.robot, v.context.held.holding()).queryTrees(from(i), v.pre[j], v.context, deadline)
                          : layer.connect(v.robot, from(i), v.pre[j], v.context, deadline);
  if (!path) {
    ++result.failed_moves;
    layer.emitter_->counter("motion_query_failed_moves", ++layer.query_failed_moves_);
    return false;
  }
  takeTransit(i, j, arc, *path);
  return true;
}

void MotionQuery::takeTransit(int i, std::size_t j, std::optional<HyperarcId> arc, const std::vector<JointVector>& path) {
  VisitAnchors& v = h.visits[i];
  pre_choice[i] = static_cast<int>(j);
  transit[i] = path;
  if (arc) {
    graph.setPath(*arc, path);
    ++hyperpath;
  }
  if (const auto approach = graph.move(v.pre_vertex[j], v.at_q, {v.pre[j], v.visit.q})) {
    graph.take(*approach);
    ++hyperpath;
  }
  at[v.robot] = v.at_q;
}

void MotionQuery::takeRetreat(int i) {
  VisitAnchors& v = h.visits[i];
  const auto c = static_cast<std::size_t>(post_choice[i]);
  if (const auto arc = graph.move(v.after_q, v.post_vertex[c], {v.visit.q, v.post[c]})) {
    graph.take(*arc);
    ++hyperpath;
  }
  at[v.robot] = v.post_vertex[c];
}

void MotionQuery::refine(int i) {
  log::PhaseTimer construction(*layer.emitter_, log::Phase::MotionConstruction);
  VisitAnchors& v = h.visits[i];
  const TaskElement before = graph.graph().property(v.at_q).element;
  if (!v.is_giver && !v.home && v.pre.size() == 1)
    if (auto pre = layer.farthestBackOff(v.robot, v.visit.q, v.visit.held_before, h.layouts[v.visit.step])) {
      v.pre.push_back(*pre);
      v.pre_vertex.push_back(graph.robotVertex(v.robot, before, *pre));
    }
  if (v.previous < 0) return;
  VisitAnchors& p = h.visits[v.previous];
  if (!p.own_axis || p.post.size() > 1) return;
  if (auto post = layer.farthestBackOff(p.robot, p.visit.q, p.visit.held_after, h.layouts[p.visit.step + 1])) {
    p.post.push_back(*post);
    p.post_vertex.push_back(graph.robotVertex(p.robot, graph.graph().property(p.after_q).element, *post));
  }
}

void MotionQuery::fail(int i) {
  const VisitAnchors& v = h.visits[i];
  const int r = v.robot;
  const JointVector& pre = v.pre.back();
  const ObjectLayout& layout = v.context.layout;
  result.status = deadline.expired() ? MotionStatus::kTimeout : MotionStatus::kFailed;
  const std::string colliding = layer.collidingEnd(r, from(i), pre, v.visit.q, v.visit.held_before, layout);
  if (v.home) {
    result.reason = "no path home for " + scene.robots[r].id + MotionLayer::whyNoPath(colliding);
    return;
  }
  result.failed_step = v.visit.step;
  result.failed_robot = r;
  result.failed_q = v.visit.q;
  result.ends_free = colliding.empty();
  const std::string in_region = layer.endInRegion(r, from(i), pre, v.context);
  const int k = v.visit.step;
  result.reason = "no path for " + scene.robots[r].id + " to step " + std::to_string(k) + " (" +
                  describeStep(plan.steps[k], *space) + ")" + MotionLayer::whyNoPath(colliding.empty() ? in_region : colliding);
}

void MotionQuery::collect() {
  for (std::size_t i = 0; i < h.visits.size(); ++i) {
    const VisitAnchors& v = h.visits[i];
    RobotMotionPlan& robot = result.robots[v.robot];
    if (v.home) {
      robot.home_path = transit[i];
      continue;
    }
    StepVisit visit = v.visit;
    visit.transit = transit[i];
    visit.q_pre = v.pre[pre_choice[i]];
    visit.q_post = v.post[post_choice[i]];
    layer.setBackOffPaths(visit, v.robot);  // the straight TCP lines between them (cartesian_path.h)
    robot.visits.push_back(std::move(visit));
  }
}

MotionLayerResult MotionLayer::query(MotionAnchors& anchors, const TaskPlan& plan, const TaskSpace& space,
                                     const Deadline& deadline) {
  // The whole query is booked as motion query; H_M's growth inside it (refine) as construction.
  log::PhaseTimer timer(*emitter_, log::Phase::MotionQuery);
  return MotionQuery{*this, anchors, plan, deadline, space.scene(), &space}.run();
}

MotionLayerResult MotionLayer::plan(const TaskPlan& plan, const std::vector<TransitionConfig>& transitions,
                                    const TaskSpace& space, const Deadline& deadline) {
  MotionAnchors anchors = construct(plan, transitions, space);
  return query(anchors, plan, space, deadline);
}

}  // namespace dash
