#include "engine/dash/transition_catalog.h"

#include <algorithm>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>

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

/// What each robot can be holding each object with (grasp and class): picks first, then whatever
/// handovers give it. [robot][object], append-only.
class ObtainableGrasps {
 public:
  ObtainableGrasps(int robots, std::size_t objects)
      : lists_(static_cast<std::size_t>(robots), std::vector<std::vector<Obtainable>>(objects)) {}
  const std::vector<Obtainable>& of(int robot, int object) const { return lists_[robot][object]; }
  /// Adds the grasp; false when the robot could already hold the object so.
  bool obtain(int robot, const HeldObject& held, GraspClass c) {
    auto& list = lists_[robot][held.object];
    for (const Obtainable& h : list)
      if (sameHeld(h.held, held)) return false;
    list.push_back({held, c});
    return true;
  }
  bool knows(int robot, int object, const Pose& X_TO) const {
    for (const Obtainable& h : lists_[robot][object])
      if (h.held.X_TO.matrix() == X_TO.matrix()) return true;
    return false;
  }

 private:
  std::vector<std::vector<std::vector<Obtainable>>> lists_;
};

/// Empty-handed back-offs (backOff) already computed in this catalog: the handover search asks for the
/// same giver and receiver configurations' back-offs again for every giver grasp and receiver grasp it
/// tries at a pose, and they depend on the static scene only. Bounded: cleared when full.
class BackOffMemo {
 public:
  const std::optional<std::vector<JointVector>>& get(TransitionSampler& sampler, int robot, const JointVector& q,
                                                     double distance, const TransitionCatalogParams& params) {
    std::string key(reinterpret_cast<const char*>(&robot), sizeof robot);
    key.append(reinterpret_cast<const char*>(&distance), sizeof distance);
    key.append(reinterpret_cast<const char*>(q.data()), sizeof(double) * static_cast<std::size_t>(q.size()));
    if (auto it = memo_.find(key); it != memo_.end()) return it->second;
    if (memo_.size() >= kMaxEntries) memo_.clear();
    return memo_.emplace(std::move(key), backOff(sampler, robot, q, HeldObject{}, distance, params)).first->second;
  }

 private:
  static constexpr std::size_t kMaxEntries = 100000;  // a few tens of MB at most
  std::unordered_map<std::string, std::optional<std::vector<JointVector>>> memo_;
};

/// Pick/place grasp samples at every placement of every object, for every pick hyperarc.
void sampleGrasps(TransitionSampler& sampler, const TaskSpace& space, const DashTaskGraph& graph,
                  const TransitionCatalogParams& params, const Deadline& deadline, ObtainableGrasps& obtainable,
                  TransitionCatalog& out) {
  for (HyperarcId a : graph.hyperarcs()) {
    const TaskArc& arc = graph.property(a);
    if (arc.type != TaskArcType::kPick) continue;
    for (int l = 0; l < static_cast<int>(space.locations(arc.object).size()); ++l) {
      if (deadline.expired()) return;
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
        obtainable.obtain(arc.robot, s.held, arc.grasp);
        out.grasps.push_back(std::move(s));
      }
    }
  }
}

/// Handovers, to a fixed point: for each handover hyperarc and each grasp the giver can have, a sample
/// delivering each grasp the receiver already has of the class (from its picks and places first, then
/// earlier handovers), up to handovers_per_grasp; a new grasp only when none of those works. A grasp a
/// robot receives may be handed on. Preferring known grasps is what lets chains of handovers (regrasps
/// included) close onto the grasps the places need.
class HandoverSearch {
 public:
  HandoverSearch(TransitionSampler& sampler, const Scene& scene, const TransitionCatalogParams& params,
                 const Deadline& deadline, ObtainableGrasps& obtainable, TransitionCatalog& out)
      : sampler_(sampler), scene_(scene), params_(params), deadline_(deadline), obtainable_(obtainable), out_(out) {}

  void run(const DashTaskGraph& graph, const std::vector<HyperarcId>& arcs);

 private:
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
  /// One pass over the giver grasps of one hyperarc; true when a receiver gained a grasp.
  bool pass(const TaskArc& arc, ArcState& st);
  /// One sample for this hyperarc and giver grasp, delivering `target` (nullptr: a grasp the receiver
  /// does not have yet). False when no object pose works.
  bool sample(const TaskArc& arc, ArcState& st, const Obtainable& g1, const Pose* target, bool& changed);
  /// The handover at X_WO with giver configuration q1 and receiver grasp gc2, if both have room to
  /// back off and its own motions are free.
  std::optional<HandoverSample> at(const TaskArc& arc, const Pose& X_WO, const Obtainable& g1, const JointVector& q1,
                                   const GraspConfig& gc2);

  TransitionSampler& sampler_;
  const Scene& scene_;
  const TransitionCatalogParams& params_;
  const Deadline& deadline_;
  ObtainableGrasps& obtainable_;
  TransitionCatalog& out_;
  BackOffMemo back_offs_;
};

void HandoverSearch::run(const DashTaskGraph& graph, const std::vector<HyperarcId>& arcs) {
  std::vector<ArcState> state(arcs.size());
  bool changed = true;
  while (changed && !deadline_.expired()) {
    changed = false;
    for (std::size_t i = 0; i < arcs.size(); ++i) changed = pass(graph.property(arcs[i]), state[i]) || changed;
  }
}

bool HandoverSearch::pass(const TaskArc& arc, ArcState& st) {
  bool changed = false;
  const auto& givers = obtainable_.of(arc.robot, arc.object);
  st.tried.resize(givers.size());
  st.tried_new.resize(givers.size(), 0);
  st.kept.resize(givers.size(), 0);
  for (std::size_t t = 0; t < givers.size(); ++t) {
    const Obtainable g1 = givers[t];  // copies: sample() may grow the lists
    if (g1.grasp != arc.grasp) continue;
    for (std::size_t u = 0; u < obtainable_.of(arc.robot2, arc.object).size(); ++u) {
      if (st.kept[t] >= params_.handovers_per_grasp) break;
      st.tried[t].resize(std::max(st.tried[t].size(), u + 1), 0);
      if (st.tried[t][u]) continue;
      st.tried[t][u] = 1;
      const Obtainable target = obtainable_.of(arc.robot2, arc.object)[u];
      if (target.grasp != arc.grasp2) continue;
      if (sample(arc, st, g1, &target.held.X_TO, changed)) ++st.kept[t];
    }
    if (st.kept[t] == 0 && !st.tried_new[t]) {
      st.tried_new[t] = 1;
      if (sample(arc, st, g1, nullptr, changed)) ++st.kept[t];
    }
  }
  return changed;
}

bool HandoverSearch::sample(const TaskArc& arc, ArcState& st, const Obtainable& g1, const Pose* target, bool& changed) {
  const int o = arc.object;
  if (st.grid == ArcState::Grid::kImpossible) return false;
  // Delivering a grasp the receiver already has looks at the start of the grid only: failing that
  // says nothing about the hyperarc.
  const bool whole_grid = st.grid == ArcState::Grid::kUnsearched && target == nullptr;
  const std::vector<Pose> poses = sampler_.handoverPoses(arc.robot, arc.robot2);
  const int pose_count = std::min<int>(whole_grid ? params_.handover_poses : params_.targeted_handover_poses,
                                       static_cast<int>(poses.size()));
  if (whole_grid) st.grid = ArcState::Grid::kImpossible;  // until a pose works
  for (int p = 0; p < pose_count; ++p) {
    if (deadline_.expired()) return false;
    const Pose& X_WO = poses[p];
    const std::vector<JointVector> givers = sampler_.holdConfigs(arc.robot, o, X_WO, g1.held.X_TO, 1, params_.approach_line);
    if (givers.empty()) continue;
    for (const GraspConfig& gc2 :
         sampler_.graspConfigs(arc.robot2, o, X_WO, arc.grasp2, kReceiverCandidates, params_.approach_line)) {
      if (target ? gc2.X_TO.matrix() != target->matrix() : obtainable_.knows(arc.robot2, o, gc2.X_TO)) continue;
      std::optional<HandoverSample> h = at(arc, X_WO, g1, givers.front(), gc2);
      if (!h) continue;
      st.grid = ArcState::Grid::kPossible;
      changed = obtainable_.obtain(arc.robot2, h->held2, arc.grasp2) || changed;
      out_.handovers.push_back(std::move(*h));
      return true;
    }
  }
  return false;
}

std::optional<HandoverSample> HandoverSearch::at(const TaskArc& arc, const Pose& X_WO, const Obtainable& g1,
                                                 const JointVector& q1, const GraspConfig& gc2) {
  const RobotState states[2] = {{arc.robot, q1, g1.held}, {arc.robot2, gc2.q, HeldObject{}}};
  if (robotsInCollision(sampler_.world(), sampler_.context(), states, ObjectLayout::empty(scene_), nullptr,
                        CheckScope::kStaticOnly))
    return std::nullopt;
  // Both need room: the receiver to approach, the giver to let go and back off.
  // A copy: the next look-up may clear the memo.
  const std::optional<std::vector<JointVector>> q1_post =
      back_offs_.get(sampler_, arc.robot, q1, params_.approach_distance, params_);
  if (!q1_post) return std::nullopt;
  const auto& q2_pre = back_offs_.get(sampler_, arc.robot2, gc2.q, params_.approach_distance, params_);
  if (!q2_pre) return std::nullopt;
  HandoverSample h;
  h.giver = arc.robot;
  h.receiver = arc.robot2;
  h.object = arc.object;
  h.grasp = arc.grasp;
  h.grasp2 = arc.grasp2;
  h.X_WO = X_WO;
  h.held = g1.held;
  h.held2 = HeldObject{arc.object, gc2.X_TO};
  h.q1 = q1;
  h.q1_post_path = *q1_post;
  h.q2 = gc2.q;
  h.q2_pre_path = *q2_pre;
  h.q2_post_path = backedOff(sampler_, arc.robot2, h.q2, h.held2, params_.approach_distance, params_);
  setEnds(h);
  if (!handoverMotionsFree(sampler_, h)) return std::nullopt;
  return h;
}

/// Inspection configurations for every inspect hyperarc.
void sampleInspects(TransitionSampler& sampler, const Scene& scene, const DashTaskGraph& graph,
                    const std::vector<HyperarcId>& arcs, const TransitionCatalogParams& params,
                    const Deadline& deadline, TransitionCatalog& out) {
  for (HyperarcId a : arcs) {
    const TaskArc& arc = graph.property(a);
    int n = 0;
    for (const JointVector& q : sampler.ikSolutions(arc.robot, scene.tasks[arc.task].X_WT)) {
      if (deadline.expired()) return;
      if (!sampler.staticFree({arc.robot, q, HeldObject{}})) continue;
      const auto pre_path = backedOff(sampler, arc.robot, q, {}, params.approach_distance, params);
      out.inspects.push_back({arc.robot, arc.task, q, pre_path.back(), pre_path});
      if (++n >= params.inspect_configs) break;
    }
  }
}

}  // namespace

TransitionCatalog sampleTransitions(TransitionSampler& sampler, const TaskSpace& space, const DashTaskGraph& graph,
                                    const TransitionCatalogParams& params, const Deadline& deadline) {
  TransitionCatalog out;
  const Scene& scene = space.scene();
  ObtainableGrasps obtainable(static_cast<int>(scene.robots.size()), scene.objects.size());
  std::vector<HyperarcId> handover_arcs, inspect_arcs;
  for (HyperarcId a : graph.hyperarcs()) {
    if (graph.property(a).type == TaskArcType::kHandover) handover_arcs.push_back(a);
    if (graph.property(a).type == TaskArcType::kInspect) inspect_arcs.push_back(a);
  }
  sampleGrasps(sampler, space, graph, params, deadline, obtainable, out);
  if (deadline.expired()) return out;
  HandoverSearch(sampler, scene, params, deadline, obtainable, out).run(graph, handover_arcs);
  sampleInspects(sampler, scene, graph, inspect_arcs, params, deadline, out);
  return out;
}

}  // namespace dash
