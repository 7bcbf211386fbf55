#pragma once
// One robot against what never moves (its own links and the obstacles), with an empty hand unless a
// held object is given: the validity that roadmaps shared by every motion context are built with
// (Lazy-PRM's static part, context_lazy_prm.h; DaSH's validated PRM, engine/dash/validated_roadmap.h).
#include "engine/collision/collision_context.h"
#include "engine/collision/collision_state.h"
#include "engine/robots/joint_vector.h"
#include "engine/scene/object_layout.h"

namespace dash {

class StaticRobotValidity {
 public:
  StaticRobotValidity(const CollisionWorld& world, CollisionContext& context, int robot);

  bool stateValid(const JointVector& q, const HeldObject& held = {}) const;
  /// The straight joint-space segment a -> b, at the segment checker's resolution.
  bool motionValid(const JointVector& a, const JointVector& b, const HeldObject& held = {}) const;

 private:
  const CollisionWorld* world_;
  CollisionContext* context_;
  int robot_;
  ObjectLayout none_;
};

}  // namespace dash
