#include "engine/dash/transition_catalog.h"

#include <algorithm>
#include <optional>
#include <span>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/robots/cartesian_path.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

constexpr int kReceiverCandidates = 8;  // receiver grasp configurations looked at per object pose

double jointDistance(const JointVector& a, const JointVector& b) { return (a - b).cwiseAbs().sum(); }

/// The path from q on which the TCP backs off by `distance` along its approach axis (rising by
/// side_lift when sideways: backOffPose) on a straight line (cartesianPath), every waypoint statically
/// free and every segment too; nullopt when there is none.
std::optional<std::vector<JointVector>> backOff(TransitionSampler& sampler, int robot, const JointVector& q,
                                                const HeldObject& held, double distance,
                                                const TransitionCatalogParams& params) {
  const CollisionWorld& world = sampler.world();
  const SceneRobot& r = world.scene().robots[robot];
  const Pose X_WT = forwardKinematics(*r.model, r.X_WB, q).X_WT;
  const ObjectLayout none = ObjectLayout::empty(world.scene());
  std::vector<JointVector> candidates = inverseKinematics(*r.model, r.X_WB, backOffPose(X_WT, distance, params.side_lift));
  std::sort(candidates.begin(), candidates.end(),
            [&](const JointVector& a, const JointVector& b) { return jointDistance(a, q) < jointDistance(b, q); });
  for (const JointVector& cand : candidates) {
    std::optional<std::vector<JointVector>> path = backOffLine(*r.model, r.X_WB, q, cand);
    if (!path) continue;
    bool free = true;
    for (std::size_t i = path->size(); free && i-- > 1;) free = sampler.staticFree({robot, (*path)[i], held});
    for (std::size_t i = path->size(); free && i-- > 1;)
      free = !segmentInCollision(world, sampler.context(), {robot, (*path)[i], held}, (*path)[i - 1], none, nullptr,
                                 SegmentOptions{.scope = CheckScope::kStaticOnly, .check_endpoints = false});
    if (free) return path;
  }
  return std::nullopt;
}

/// backOff, or q alone when there is no room (the transition then starts and ends right there).
std::vector<JointVector> backedOff(TransitionSampler& sampler, int robot, const JointVector& q, const HeldObject& held,
                                   double distance, const TransitionCatalogParams& params) {
  return backOff(sampler, robot, q, held, distance, params).value_or(std::vector<JointVector>{q});
}

/// The back-off a grasp sample uses: for a side grasp the farthest free deep back-off, else (or when
/// none is free) the short one, else q alone.
std::vector<JointVector> graspBackOff(TransitionSampler& sampler, int robot, const JointVector& q,
                                      const HeldObject& held, GraspClass grasp, const TransitionCatalogParams& params) {
  if (grasp == GraspClass::kSide)
    for (auto it = params.deep_approach_distances.rbegin(); it != params.deep_approach_distances.rend(); ++it)
      if (auto deep = backOff(sampler, robot, q, held, *it, params)) return *deep;
  return backedOff(sampler, robot, q, held, params.approach_distance, params);
}

/// The back-off ends of a sample: the last configuration of each of its back-off paths.
void setEnds(GraspSample& s) {
  s.q_pre = s.pre_path.back();
  s.q_hold = s.hold_path.back();
}
void setEnds(HandoverSample& h) {
  h.q1_post = h.q1_post_path.back();
  h.q2_pre = h.q2_pre_path.back();
  h.q2_post = h.q2_post_path.back();
}

/// Whether robot `mover` moving along `path` (held throughout) meets robot `still` standing there.
bool pathMeetsStanding(TransitionSampler& sampler, const RobotState& mover, const std::vector<JointVector>& path,
                       const RobotState& still) {
  const ObjectLayout none = ObjectLayout::empty(sampler.world().scene());
  for (std::size_t i = 1; i < path.size(); ++i) {
    const RobotMotion motions[2] = {{{mover.robot, path[i - 1], mover.held}, path[i]}, {still, still.q}};
    if (motionsInCollision(sampler.world(), sampler.context(), std::span<const RobotMotion>(motions, 2), none, nullptr,
                           SegmentOptions{.scope = CheckScope::kStaticOnly}))
      return true;
  }
  return false;
}

/// The handover's own motions, with both robots: the receiver's approach while the giver holds the
/// object in place, the giver's retreat while the receiver holds it, the receiver's retreat.
bool handoverMotionsFree(TransitionSampler& sampler, const HandoverSample& h) {
  return !pathMeetsStanding(sampler, {h.receiver, h.q2, {}}, h.q2_pre_path, {h.giver, h.q1, h.held}) &&
         !pathMeetsStanding(sampler, {h.giver, h.q1, {}}, h.q1_post_path, {h.receiver, h.q2, h.held2}) &&
         !pathMeetsStanding(sampler, {h.receiver, h.q2, h.held2}, h.q2_post_path, {h.giver, h.q1_post, {}});
}

struct Obtainable {
  HeldObject held;
  GraspClass grasp = GraspClass::kTop;
};

bool sameHeld(const HeldObject& a, const HeldObject& b) {
  return a.object == b.object && a.X_TO.matrix() == b.X_TO.matrix();
}

}  // namespace

TransitionCatalog sampleTransitions(TransitionSampler& sampler, const TaskSpace& space, const DashTaskGraph& graph,
                                    const TransitionCatalogParams& params, const Deadline& deadline) {
  TransitionCatalog out;
  const Scene& scene = space.scene();
  const int robots = static_cast<int>(scene.robots.size());
  // What each robot can be holding each object with (grasp and class): picks first, then whatever
  // handovers give it.
  std::vector<std::vector<std::vector<Obtainable>>> obtainable(
      static_cast<std::size_t>(robots), std::vector<std::vector<Obtainable>>(scene.objects.size()));
  auto obtain = [&](int r, const HeldObject& held, GraspClass c) {
    auto& list = obtainable[r][held.object];
    for (const Obtainable& h : list)
      if (sameHeld(h.held, held)) return false;
    list.push_back({held, c});
    return true;
  };

  std::vector<HyperarcId> handover_arcs, inspect_arcs;
  for (HyperarcId a : graph.hyperarcs()) {
    const TaskArc& arc = graph.property(a);
    if (arc.type == TaskArcType::kHandover) handover_arcs.push_back(a);
    if (arc.type == TaskArcType::kInspect) inspect_arcs.push_back(a);
    if (arc.type != TaskArcType::kPick) continue;
    for (int l = 0; l < static_cast<int>(space.locations(arc.object).size()); ++l) {
      if (deadline.expired()) return out;
      const Pose& X_WO = space.location(arc.object, l).X_WO;
      for (const GraspConfig& gc :
           sampler.graspConfigs(arc.robot, arc.object, X_WO, arc.grasp, params.grasps_per_class, params.approach_line)) {
        GraspSample s;
        s.robot = arc.robot;
        s.object = arc.object;
        s.placement = l;
        s.grasp = arc.grasp;
        s.held = HeldObject{arc.object, gc.X_TO};
        s.q = gc.q;
        s.pre_path = graspBackOff(sampler, arc.robot, gc.q, HeldObject{}, arc.grasp, params);
        s.hold_path = graspBackOff(sampler, arc.robot, gc.q, s.held, arc.grasp, params);
        setEnds(s);
        obtain(arc.robot, s.held, arc.grasp);
        out.grasps.push_back(std::move(s));
      }
    }
  }

  // Handovers, to a fixed point: for each handover hyperarc and each grasp the giver can have, a
  // sample delivering each grasp the receiver already has of the class (from its picks and places
  // first, then earlier handovers), up to handovers_per_grasp; a new grasp only when none of those
  // works. A grasp a robot receives may be handed on. Preferring known grasps is what lets chains of
  // handovers (regrasps included) close onto the grasps the places need.
  struct ArcState {
    std::vector<std::vector<char>> tried;  ///< [giver grasp][receiver grasp]
    std::vector<char> tried_new;           ///< [giver grasp]
    std::vector<int> kept;                 ///< [giver grasp]
    /// The whole pose grid is searched once per hyperarc (its first search, for any grasp): when it
    /// finds nothing the hyperarc is impossible, as Lazy-DaSH's handoverPossible cache (one entry per
    /// giver, receiver, object and class pair, i.e. per hyperarc) concludes; later searches on a
    /// possible hyperarc look at the start of the grid only.
    enum class Grid { kUnsearched, kPossible, kImpossible } grid = Grid::kUnsearched;
  };
  std::vector<ArcState> state(handover_arcs.size());
  // One sample for this hyperarc and giver grasp, delivering `target` (nullptr: a grasp the receiver
  // does not have yet). False when no object pose works.
  auto sample = [&](const TaskArc& arc, ArcState& st, const Obtainable& g1, const Pose* target, bool& changed) {
    const int o = arc.object;
    if (st.grid == ArcState::Grid::kImpossible) return false;
    // Delivering a grasp the receiver already has looks at the start of the grid only: failing that
    // says nothing about the hyperarc.
    const bool whole_grid = st.grid == ArcState::Grid::kUnsearched && target == nullptr;
    const std::vector<Pose> poses = sampler.handoverPoses(arc.robot, arc.robot2);
    const int pose_count = std::min<int>(whole_grid ? params.handover_poses : params.targeted_handover_poses,
                                         static_cast<int>(poses.size()));
    if (whole_grid) st.grid = ArcState::Grid::kImpossible;  // until a pose works
    auto known = [&](const Pose& X_TO) {
      for (const Obtainable& h : obtainable[arc.robot2][o])
        if (h.held.X_TO.matrix() == X_TO.matrix()) return true;
      return false;
    };
    for (int p = 0; p < pose_count; ++p) {
      if (deadline.expired()) return false;
      const Pose& X_WO = poses[p];
      const std::vector<JointVector> givers = sampler.holdConfigs(arc.robot, o, X_WO, g1.held.X_TO, 1, params.approach_line);
      if (givers.empty()) continue;
      for (const GraspConfig& gc2 : sampler.graspConfigs(arc.robot2, o, X_WO, arc.grasp2, kReceiverCandidates, params.approach_line)) {
        if (target ? gc2.X_TO.matrix() != target->matrix() : known(gc2.X_TO)) continue;
        const RobotState states[2] = {{arc.robot, givers.front(), g1.held}, {arc.robot2, gc2.q, HeldObject{}}};
        if (robotsInCollision(sampler.world(), sampler.context(), states, ObjectLayout::empty(scene), nullptr,
                              CheckScope::kStaticOnly))
          continue;
        // Both need room: the receiver to approach, the giver to let go and back off.
        const auto q1_post = backOff(sampler, arc.robot, givers.front(), HeldObject{}, params.approach_distance, params);
        const auto q2_pre = backOff(sampler, arc.robot2, gc2.q, HeldObject{}, params.approach_distance, params);
        if (!q1_post || !q2_pre) continue;
        HandoverSample h;
        h.giver = arc.robot;
        h.receiver = arc.robot2;
        h.object = o;
        h.grasp = arc.grasp;
        h.grasp2 = arc.grasp2;
        h.X_WO = X_WO;
        h.held = g1.held;
        h.held2 = HeldObject{o, gc2.X_TO};
        h.q1 = givers.front();
        h.q1_post_path = *q1_post;
        h.q2 = gc2.q;
        h.q2_pre_path = *q2_pre;
        h.q2_post_path = backedOff(sampler, arc.robot2, h.q2, h.held2, params.approach_distance, params);
        setEnds(h);
        if (!handoverMotionsFree(sampler, h)) continue;
        st.grid = ArcState::Grid::kPossible;
        changed = obtain(arc.robot2, h.held2, arc.grasp2) || changed;
        out.handovers.push_back(std::move(h));
        return true;
      }
    }
    return false;
  };
  bool changed = true;
  while (changed && !deadline.expired()) {
    changed = false;
    for (std::size_t i = 0; i < handover_arcs.size(); ++i) {
      const TaskArc& arc = graph.property(handover_arcs[i]);
      ArcState& st = state[i];
      const auto& givers = obtainable[arc.robot][arc.object];
      st.tried.resize(givers.size());
      st.tried_new.resize(givers.size(), 0);
      st.kept.resize(givers.size(), 0);
      for (std::size_t t = 0; t < givers.size(); ++t) {
        const Obtainable g1 = givers[t];  // copies: sample() may grow the lists
        if (g1.grasp != arc.grasp) continue;
        for (std::size_t u = 0; u < obtainable[arc.robot2][arc.object].size(); ++u) {
          if (st.kept[t] >= params.handovers_per_grasp) break;
          st.tried[t].resize(std::max(st.tried[t].size(), u + 1), 0);
          if (st.tried[t][u]) continue;
          st.tried[t][u] = 1;
          const Obtainable target = obtainable[arc.robot2][arc.object][u];
          if (target.grasp != arc.grasp2) continue;
          if (sample(arc, st, g1, &target.held.X_TO, changed)) ++st.kept[t];
        }
        if (st.kept[t] == 0 && !st.tried_new[t]) {
          st.tried_new[t] = 1;
          if (sample(arc, st, g1, nullptr, changed)) ++st.kept[t];
        }
      }
    }
  }

  for (HyperarcId a : inspect_arcs) {
    const TaskArc& arc = graph.property(a);
    int n = 0;
    for (const JointVector& q : sampler.ikSolutions(arc.robot, scene.tasks[arc.task].X_WT)) {
      if (deadline.expired()) return out;
      if (!sampler.staticFree({arc.robot, q, HeldObject{}})) continue;
      const auto pre_path = backedOff(sampler, arc.robot, q, {}, params.approach_distance, params);
      out.inspects.push_back({arc.robot, arc.task, q, pre_path.back(), pre_path});
      if (++n >= params.inspect_configs) break;
    }
  }
  return out;
}

}  // namespace dash
