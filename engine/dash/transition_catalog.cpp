#include "engine/dash/transition_catalog.h"

#include <algorithm>
#include <optional>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

constexpr int kReceiverCandidates = 8;  // receiver grasp configurations looked at per object pose

double jointDistance(const JointVector& a, const JointVector& b) { return (a - b).cwiseAbs().sum(); }

/// q with the TCP backed off by `distance` along its approach axis, statically free and reachable by
/// a free straight segment; q itself when there is none (the transition then starts right there).
JointVector backedOff(TransitionSampler& sampler, int robot, const JointVector& q, const HeldObject& held,
                      double distance) {
  const CollisionWorld& world = sampler.world();
  const SceneRobot& r = world.scene().robots[robot];
  const Pose X_WT = forwardKinematics(*r.model, r.X_WB, q).X_WT;
  const Pose X_WTpre = X_WT * makePose(Vec3(0, 0, -distance));
  const ObjectLayout none = ObjectLayout::empty(world.scene());
  std::optional<JointVector> best;
  for (const JointVector& cand : inverseKinematics(*r.model, r.X_WB, X_WTpre)) {
    if (best && jointDistance(cand, q) >= jointDistance(*best, q)) continue;
    const RobotState state{robot, cand, held};
    if (!sampler.staticFree(state)) continue;
    if (segmentInCollision(world, sampler.context(), state, q, none, nullptr,
                           SegmentOptions{.scope = CheckScope::kStaticOnly}))
      continue;
    best = cand;
  }
  return best.value_or(q);
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
      for (const GraspConfig& gc : sampler.graspConfigs(arc.robot, arc.object, X_WO, arc.grasp, params.grasps_per_class)) {
        GraspSample s;
        s.robot = arc.robot;
        s.object = arc.object;
        s.placement = l;
        s.grasp = arc.grasp;
        s.held = HeldObject{arc.object, gc.X_TO};
        s.q = gc.q;
        s.q_pre = backedOff(sampler, arc.robot, gc.q, HeldObject{}, params.approach_distance);
        s.q_hold = backedOff(sampler, arc.robot, gc.q, s.held, params.approach_distance);
        obtain(arc.robot, s.held, arc.grasp);
        out.grasps.push_back(std::move(s));
      }
    }
  }

  // Handovers, to a fixed point: one sample per handover hyperarc and grasp the giver can have, and a
  // grasp a robot receives may be handed on. The receiver takes, where it can, a grasp it already
  // has (from a pick, a place or an earlier handover), so that chains of handovers close onto the
  // grasps its places need instead of each opening a planning space of its own.
  std::vector<std::vector<char>> tried(handover_arcs.size());
  bool changed = true;
  while (changed) {
    changed = false;
    for (std::size_t i = 0; i < handover_arcs.size(); ++i) {
      const TaskArc& arc = graph.property(handover_arcs[i]);
      const int o = arc.object;
      const std::vector<Pose> poses = sampler.handoverPoses(arc.robot, arc.robot2);
      const int pose_count = std::min<int>(params.handover_poses, static_cast<int>(poses.size()));
      for (std::size_t t = 0; t < obtainable[arc.robot][o].size(); ++t) {
        if (t < tried[i].size() && tried[i][t]) continue;
        tried[i].resize(std::max(tried[i].size(), t + 1), 0);
        tried[i][t] = 1;
        const Obtainable g1 = obtainable[arc.robot][o][t];  // a copy: obtain() below may grow the list
        if (g1.grasp != arc.grasp) continue;
        auto known = [&](const Pose& X_TO) {
          for (const Obtainable& h : obtainable[arc.robot2][o])
            if (h.held.X_TO.matrix() == X_TO.matrix()) return true;
          return false;
        };
        int kept = 0;
        for (int pass = 0; pass < 2 && kept < params.handovers_per_grasp; ++pass) {
          for (int p = 0; p < pose_count && kept < params.handovers_per_grasp; ++p) {
            if (deadline.expired()) return out;
            const Pose& X_WO = poses[p];
            const std::vector<JointVector> givers = sampler.holdConfigs(arc.robot, o, X_WO, g1.held.X_TO, 1);
            if (givers.empty()) continue;
            for (const GraspConfig& gc2 : sampler.graspConfigs(arc.robot2, o, X_WO, arc.grasp2, kReceiverCandidates)) {
              if (known(gc2.X_TO) != (pass == 0)) continue;  // pass 0: grasps it has; pass 1: new ones
              const RobotState states[2] = {{arc.robot, givers.front(), g1.held}, {arc.robot2, gc2.q, HeldObject{}}};
              if (robotsInCollision(sampler.world(), sampler.context(), states, ObjectLayout::empty(scene), nullptr,
                                    CheckScope::kStaticOnly))
                continue;
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
              h.q1_post = backedOff(sampler, arc.robot, h.q1, HeldObject{}, params.approach_distance);
              h.q2 = gc2.q;
              h.q2_pre = backedOff(sampler, arc.robot2, h.q2, HeldObject{}, params.approach_distance);
              h.q2_post = backedOff(sampler, arc.robot2, h.q2, h.held2, params.approach_distance);
              changed = obtain(arc.robot2, h.held2, arc.grasp2) || changed;
              out.handovers.push_back(std::move(h));
              ++kept;
              break;  // one per object pose
            }
          }
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
      out.inspects.push_back({arc.robot, arc.task, q, backedOff(sampler, arc.robot, q, {}, params.approach_distance)});
      if (++n >= params.inspect_configs) break;
    }
  }
  return out;
}

}  // namespace dash
