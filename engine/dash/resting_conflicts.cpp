#include "engine/dash/resting_conflicts.h"

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"

namespace dash {

namespace {

/// The robot's own vertex in the tail of hyperarc a (where it must be to start it).
VertexId robotTailVertex(const MotionGraph& g, HyperarcId a, int robot) {
  for (VertexId v : g.tail(a)) {
    const MotionVertex& mv = g.property(v);
    if ((mv.kind == MotionVertex::Kind::kRobot || mv.kind == MotionVertex::Kind::kHolding) && mv.robot == robot) return v;
  }
  return {};
}

class Checker {
 public:
  Checker(const CollisionWorld& world, CollisionContext& context) : world_(world), context_(context) {}
  bool stateHits(int robot, const JointVector& q, const HeldObject& held, const ObjectLayout& layout) {
    return robotInCollision(world_, context_, RobotState{robot, q, held}, layout, nullptr, CheckScope::kObjectsOnly);
  }
  bool segmentHits(int robot, const JointVector& a, const JointVector& b, const HeldObject& held,
                   const ObjectLayout& layout) {
    return segmentInCollision(world_, context_, RobotState{robot, a, held}, b, layout, nullptr,
                              SegmentOptions{.scope = CheckScope::kObjectsOnly});
  }
  bool pathHits(int robot, const std::vector<JointVector>& path, const HeldObject& held, const ObjectLayout& layout) {
    for (std::size_t i = 1; i < path.size(); ++i)
      if (segmentHits(robot, path[i - 1], path[i], held, layout)) return true;
    return path.size() == 1 && stateHits(robot, path.front(), held, layout);
  }

 private:
  const CollisionWorld& world_;
  CollisionContext& context_;
};

// Greedy shortcut: from each kept vertex, the farthest later vertex a free straight segment reaches.
bool shortcut(std::vector<JointVector>& path, int robot, const HeldObject& held, const CollisionWorld& world,
              CollisionContext& context, const ObjectLayout& none) {
  if (path.size() < 3) return false;
  auto free = [&](const JointVector& a, const JointVector& b) {
    return !segmentInCollision(world, context, RobotState{robot, a, held}, b, none, nullptr,
                               SegmentOptions{.scope = CheckScope::kStaticOnly});
  };
  std::vector<JointVector> out{path.front()};
  std::size_t i = 0;
  while (i + 1 < path.size()) {
    std::size_t j = path.size() - 1;
    while (j > i + 1 && !free(path[i], path[j])) --j;
    out.push_back(path[j]);
    i = j;
  }
  const bool shorter = out.size() < path.size();
  path = std::move(out);
  return shorter;
}

// One pass of resolveRestingConflicts, its steps as methods: per robot, per visit in plan order, the
// transition's configurations (no replanning moves them), then the transit (replanned round the resting
// objects where it hits one); last the way home.
class RestingConflictResolver {
 public:
  RestingConflictResolver(ExtractedPlan& plan, const MotionHypergraph& graph, const CollisionWorld& world,
                          CollisionContext& context, RoadmapSet& roadmaps, const Deadline& deadline,
                          RestingConflictStats& stats)
      : plan_(plan), graph_(graph), space_(graph.space()), scene_(space_.scene()),
        along_(restingAlong(plan.plan, space_)), layouts_(along_.layouts), check_(world, context),
        roadmaps_(roadmaps), deadline_(deadline), stats_(stats) {}

  std::optional<MotionConflict> run() {
    for (int r = 0; r < static_cast<int>(plan_.motion.robots.size()); ++r) {
      RobotMotionPlan& robot = plan_.motion.robots[r];
      for (StepVisit& v : robot.visits) {
        if (auto c = checkTransition(r, v)) return c;
        if (auto c = checkTransit(r, v)) return c;
      }
      if (auto c = checkHome(r, robot)) return c;
    }
    return std::nullopt;
  }

 private:
  // The H_M vertex of the first object resting at step `at` for which `hits` holds alone (invalid if
  // none does: then only the objects together are in the way, and the constraint holds always).
  template <class Hits>
  VertexId blocker(int at, Hits hits) const {
    const std::vector<int>& where = along_.locations[at];
    for (int o = 0; o < static_cast<int>(where.size()); ++o) {
      if (where[o] < 0) continue;
      ObjectLayout one = ObjectLayout::empty(scene_);
      one.place(o, space_.location(o, where[o]).X_WO);
      if (hits(one)) return graph_.objectVertex(o, where[o]);
    }
    return VertexId();
  }

  bool moveHits(int r, HyperarcId move, const HeldObject& held, const ObjectLayout& layout) {
    return check_.pathHits(r, graph_.move(graph_.graph().property(move).index).path, held, layout);
  }

  // The first of `moves` whose own path hits `layout`, else `fallback`.
  HyperarcId firstHitMove(int r, const std::vector<HyperarcId>& moves, HyperarcId fallback, const HeldObject& held,
                          const ObjectLayout& layout) {
    for (HyperarcId m : moves)
      if (moveHits(r, m, held, layout)) return m;
    return fallback;
  }

  std::optional<MotionConflict> checkTransition(int r, const StepVisit& v) {
    const int k = v.step;
    const HyperarcId transition = plan_.plan.steps[k].arc;
    const HeldObject& at_q = v.held_before.holding() ? v.held_before : v.held_after;
    auto approachHits = [&](const ObjectLayout& l) {
      return check_.stateHits(r, v.q, at_q, l) || check_.pathHits(r, v.approach, v.held_before, l);
    };
    auto retreatHits = [&](const ObjectLayout& l) {
      return check_.stateHits(r, v.q_post, v.held_after, l) || check_.pathHits(r, v.retreat, v.held_after, l);
    };
    const bool pre_hits = check_.stateHits(r, v.q_pre, v.held_before, layouts_[k]);
    if (!pre_hits && !approachHits(layouts_[k]) && !retreatHits(layouts_[k + 1])) return std::nullopt;
    MotionConstraint c;
    c.robot = r;
    if (pre_hits) {  // the robot may not wait at q_pre while the object rests there
      c.vertex = robotTailVertex(graph_.graph(), transition, r);
      c.while_resting = blocker(k, [&](const ObjectLayout& l) { return check_.stateHits(r, v.q_pre, v.held_before, l); });
    } else {
      c.edge = transition;
      c.while_resting = approachHits(layouts_[k]) ? blocker(k, approachHits) : blocker(k + 1, retreatHits);
    }
    if (!c.vertex.valid() && !c.edge.valid()) c.edge = transition;
    return MotionConflict{MotionConflict::Kind::kTransition, k, {r}, {transition}, {c},
                          "step " + std::to_string(k) + " (" + describeStep(plan_.plan.steps[k], space_) +
                              "): a transition configuration of " + scene_.robots[r].id + " hits a resting object"};
  }

  std::optional<MotionConflict> checkTransit(int r, StepVisit& v) {
    const int k = v.step;
    if (!check_.pathHits(r, v.transit, v.held_before, layouts_[k])) return std::nullopt;
    const MotionContext ctx{v.held_before, layouts_[k], {}};
    auto& roadmap = roadmaps_.at(r, v.held_before.holding());
    if (auto path = roadmap.plan(v.transit.front(), v.transit.back(), ctx, deadline_)) {
      v.transit = std::move(*path);
      ++stats_.replans;
      return std::nullopt;
    }
    // No way round: the conflict names the move whose own path hits a resting object (else the last).
    const HyperarcId transition = plan_.plan.steps[k].arc;
    const std::vector<HyperarcId>& moves = plan_.step_moves[k][v.receiver ? 1 : 0];
    const HyperarcId hit =
        firstHitMove(r, moves, moves.empty() ? transition : moves.back(), v.held_before, layouts_[k]);
    MotionConstraint c;
    c.robot = r;
    c.edge = hit;
    if (hit != transition)
      c.while_resting = blocker(k, [&](const ObjectLayout& l) { return moveHits(r, hit, v.held_before, l); });
    return MotionConflict{MotionConflict::Kind::kMove, k, {r}, {hit}, {c},
                          scene_.robots[r].id + " has no way round the resting objects to step " + std::to_string(k) +
                              " (" + describeStep(plan_.plan.steps[k], space_) + ")"};
  }

  std::optional<MotionConflict> checkHome(int r, RobotMotionPlan& robot) {
    if (robot.home_path.size() < 2 || !check_.pathHits(r, robot.home_path, HeldObject{}, layouts_.back()))
      return std::nullopt;
    const MotionContext ctx{{}, layouts_.back(), {}};
    if (auto path = roadmaps_.at(r, false).plan(robot.home_path.front(), robot.home_path.back(), ctx, deadline_)) {
      robot.home_path = std::move(*path);
      ++stats_.replans;
      return std::nullopt;
    }
    const std::vector<HyperarcId>& moves = plan_.home_moves[r];
    const HyperarcId hit = firstHitMove(r, moves, moves.back(), HeldObject{}, layouts_.back());
    MotionConstraint c;
    c.robot = r;
    c.edge = hit;
    c.while_resting = blocker(static_cast<int>(layouts_.size()) - 1,
                              [&](const ObjectLayout& l) { return moveHits(r, hit, HeldObject{}, l); });
    return MotionConflict{MotionConflict::Kind::kMove, -1, {r}, {hit}, {c},
                          scene_.robots[r].id + " has no way home round the resting objects"};
  }

  ExtractedPlan& plan_;
  const MotionHypergraph& graph_;
  const TaskSpace& space_;
  const Scene& scene_;
  const RestingAlongPlan along_;
  const std::vector<ObjectLayout>& layouts_;
  Checker check_;
  RoadmapSet& roadmaps_;
  const Deadline& deadline_;
  RestingConflictStats& stats_;
};

}  // namespace

int shortcutPaths(ExtractedPlan& plan, const CollisionWorld& world, CollisionContext& context) {
  const ObjectLayout none = ObjectLayout::empty(world.scene());
  int shortened = 0;
  for (int r = 0; r < static_cast<int>(plan.motion.robots.size()); ++r) {
    RobotMotionPlan& robot = plan.motion.robots[r];
    for (StepVisit& v : robot.visits) shortened += shortcut(v.transit, r, v.held_before, world, context, none) ? 1 : 0;
    shortened += shortcut(robot.home_path, r, HeldObject{}, world, context, none) ? 1 : 0;
  }
  return shortened;
}

std::optional<MotionConflict> resolveRestingConflicts(ExtractedPlan& plan, const MotionHypergraph& graph,
                                                      const CollisionWorld& world, CollisionContext& context,
                                                      RoadmapSet& roadmaps, const Deadline& deadline,
                                                      RestingConflictStats& stats) {
  return RestingConflictResolver(plan, graph, world, context, roadmaps, deadline, stats).run();
}

}  // namespace dash
