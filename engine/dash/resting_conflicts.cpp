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
  const TaskSpace& space = graph.space();
  const Scene& scene = space.scene();
  const RestingAlongPlan along = restingAlong(plan.plan, space);
  const std::vector<ObjectLayout>& layouts = along.layouts;
  Checker check(world, context);
  // The H_M vertex of the first object resting at step `at` for which `hits` holds alone (invalid if
  // none does: then only the objects together are in the way, and the constraint holds always).
  auto blocker = [&](int at, auto hits) {
    const std::vector<int>& where = along.locations[at];
    for (int o = 0; o < static_cast<int>(where.size()); ++o) {
      if (where[o] < 0) continue;
      ObjectLayout one = ObjectLayout::empty(scene);
      one.place(o, space.location(o, where[o]).X_WO);
      if (hits(one)) return graph.objectVertex(o, where[o]);
    }
    return VertexId();
  };
  for (int r = 0; r < static_cast<int>(plan.motion.robots.size()); ++r) {
    RobotMotionPlan& robot = plan.motion.robots[r];
    for (StepVisit& v : robot.visits) {
      const int k = v.step;
      const int role = v.receiver ? 1 : 0;
      const HyperarcId transition = plan.plan.steps[k].arc;
      const HeldObject& at_q = v.held_before.holding() ? v.held_before : v.held_after;
      auto approachHits = [&](const ObjectLayout& l) {
        return check.stateHits(r, v.q, at_q, l) || check.pathHits(r, v.approach, v.held_before, l);
      };
      auto retreatHits = [&](const ObjectLayout& l) {
        return check.stateHits(r, v.q_post, v.held_after, l) || check.pathHits(r, v.retreat, v.held_after, l);
      };
      const bool pre_hits = check.stateHits(r, v.q_pre, v.held_before, layouts[k]);
      if (pre_hits || approachHits(layouts[k]) || retreatHits(layouts[k + 1])) {
        MotionConstraint c;
        c.robot = r;
        if (pre_hits) {  // the robot may not wait at q_pre while the object rests there
          c.vertex = robotTailVertex(graph.graph(), transition, r);
          c.while_resting = blocker(k, [&](const ObjectLayout& l) { return check.stateHits(r, v.q_pre, v.held_before, l); });
        } else {
          c.edge = transition;
          c.while_resting = approachHits(layouts[k]) ? blocker(k, approachHits) : blocker(k + 1, retreatHits);
        }
        if (!c.vertex.valid() && !c.edge.valid()) c.edge = transition;
        return MotionConflict{MotionConflict::Kind::kTransition, k, {r}, {transition}, {c},
                              "step " + std::to_string(k) + " (" + describeStep(plan.plan.steps[k], space) +
                                  "): a transition configuration of " + scene.robots[r].id + " hits a resting object"};
      }
      if (!check.pathHits(r, v.transit, v.held_before, layouts[k])) continue;
      const MotionContext ctx{v.held_before, layouts[k], {}};
      auto& roadmap = roadmaps.at(r, v.held_before.holding());
      if (auto path = roadmap.plan(v.transit.front(), v.transit.back(), ctx, deadline)) {
        v.transit = std::move(*path);
        ++stats.replans;
        continue;
      }
      // No way round: the conflict names the move whose own path hits a resting object (else the last).
      const std::vector<HyperarcId>& moves = plan.step_moves[k][role];
      HyperarcId hit = moves.empty() ? transition : moves.back();
      for (HyperarcId m : moves)
        if (check.pathHits(r, graph.move(graph.graph().property(m).index).path, v.held_before, layouts[k])) {
          hit = m;
          break;
        }
      MotionConstraint c;
      c.robot = r;
      c.edge = hit;
      if (hit != transition)
        c.while_resting = blocker(k, [&](const ObjectLayout& l) {
          return check.pathHits(r, graph.move(graph.graph().property(hit).index).path, v.held_before, l);
        });
      return MotionConflict{MotionConflict::Kind::kMove, k, {r}, {hit}, {c},
                            scene.robots[r].id + " has no way round the resting objects to step " + std::to_string(k) +
                                " (" + describeStep(plan.plan.steps[k], space) + ")"};
    }
    if (robot.home_path.size() < 2 || !check.pathHits(r, robot.home_path, HeldObject{}, layouts.back())) continue;
    const MotionContext ctx{{}, layouts.back(), {}};
    if (auto path = roadmaps.at(r, false).plan(robot.home_path.front(), robot.home_path.back(),
                                                                     ctx, deadline)) {
      robot.home_path = std::move(*path);
      ++stats.replans;
      continue;
    }
    HyperarcId hit = plan.home_moves[r].back();
    for (HyperarcId m : plan.home_moves[r])
      if (check.pathHits(r, graph.move(graph.graph().property(m).index).path, HeldObject{}, layouts.back())) {
        hit = m;
        break;
      }
    MotionConstraint c;
    c.robot = r;
    c.edge = hit;
    c.while_resting = blocker(static_cast<int>(layouts.size()) - 1, [&](const ObjectLayout& l) {
      return check.pathHits(r, graph.move(graph.graph().property(hit).index).path, HeldObject{}, l);
    });
    return MotionConflict{MotionConflict::Kind::kMove, -1, {r}, {hit}, {c},
                          scene.robots[r].id + " has no way home round the resting objects"};
  }
  return std::nullopt;
}

}  // namespace dash
