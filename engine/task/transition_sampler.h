#pragma once
// Transition configurations: robot configurations at picks, placements and handovers, by IK of grasp
// candidates (engine/collision/grasp_candidates.h) and collision checks. Used by H_T reachability
// (static checks only) and by task conflict detection (against the objects resting at that moment).
#include <string>
#include <unordered_map>
#include <vector>

#include "engine/collision/collision_context.h"
#include "engine/collision/collision_state.h"
#include "engine/collision/grasp_candidates.h"
#include "engine/scene/object_layout.h"
#include "engine/task/task_element.h"

namespace dash {

/// A robot configuration holding (or about to hold) an object with a grasp.
struct GraspConfig {
  JointVector q;
  Pose X_TO = Pose::Identity();
  GraspCandidate::Face face = GraspCandidate::Face::kTop;
};

/// The class of a grasp as seen in the world: the approach direction (TCP z) pointing down is a top
/// grasp, pointing up a bottom grasp, anything else a side grasp.
GraspClass classifyGrasp(const Pose& X_WT);

class TransitionSampler {
 public:
  /// `context` must belong to `world`; both must outlive the sampler.
  TransitionSampler(const CollisionWorld& world, CollisionContext& context);

  const CollisionWorld& world() const { return *world_; }
  CollisionContext& context() { return *context_; }

  /// Quick range test: could robot r's TCP get near p_W at all?
  bool inRange(int robot, const Vec3& p_W) const;
  /// IK solutions for a TCP pose, closest to the robot's home first.
  std::vector<JointVector> ikSolutions(int robot, const Pose& X_WT) const;
  /// Configurations grasping `object` at X_WO with a grasp of class g that are free of self and
  /// obstacle collisions while holding it. At most `limit` (closest to home first).
  /// With `approach`, side grasps prefer the IK branch whose approach line is free (approachLineFree).
  std::vector<GraspConfig> graspConfigs(int robot, int object, const Pose& X_WO, GraspClass g, int limit = 8,
                                        bool approach = false);
  /// Configurations holding `object` with the fixed grasp X_TO while it is at X_WO, statically free;
  /// with `approach`, side grasps with a free approach line first.
  std::vector<JointVector> holdConfigs(int robot, int object, const Pose& X_WO, const Pose& X_TO, int limit = 4,
                                       bool approach = false);
  /// The TCP can back off from q in a straight line along its approach axis, on the same IK branch,
  /// by `distance`, clear of itself and the static scene: the way into and out of a shelf cubby (an arm
  /// folded the other way may have no way out).
  bool approachLineFree(int robot, const JointVector& q, const HeldObject& held, double distance);
  /// Self and obstacle collisions only.
  bool staticFree(const RobotState& state);
  /// Objects of `layout` that the robot (and what it holds) collides with, found one by one. Empty
  /// when the configuration is free of objects.
  std::vector<int> blockingObjects(const RobotState& state, ObjectLayout layout);
  /// Object poses for a handover between two robots, the default (midpoint, upright) first.
  std::vector<Pose> handoverPoses(int giver, int receiver) const;

 private:
  std::vector<GraspConfig> computeGraspConfigs(int robot, int object, const Pose& X_WO, GraspClass g, int limit,
                                               bool approach);
  std::vector<JointVector> computeHoldConfigs(int robot, int object, const Pose& X_WO, const Pose& X_TO, int limit,
                                              bool approach);

  const CollisionWorld* world_;
  CollisionContext* context_;
  ObjectLayout no_objects_;
  // graspConfigs and holdConfigs depend on the static scene only, and task conflict detection asks for the
  // same ones again after every constraint: answers are kept (bounded; keyed by the exact arguments).
  std::unordered_map<std::string, std::vector<GraspConfig>> grasp_memo_;
  std::unordered_map<std::string, std::vector<JointVector>> hold_memo_;
};

}  // namespace dash
