#include "engine/conflict/parking.h"

#include "engine/collision/collision_queries.h"

namespace dash {

namespace {
constexpr double kPi = 3.141592653589793;
constexpr double kTurns[] = {1.2, -1.2, 2.4, -2.4};  // shoulder pan offsets from home, radians

std::vector<JointVector> candidatesFor(const SceneRobot& robot) {
  std::vector<JointVector> out{robot.home};
  if (robot.model->kinematics != KinematicsKind::kUrDh) return out;
  // Upright above the base: shoulder and elbow straight up, the wrist folded over.
  JointVector upright = robot.home;
  upright[1] = -kPi / 2;
  upright[2] = 0.0;
  upright[3] = -kPi / 2;
  for (const double turn : kTurns) {
    JointVector turned = robot.home;
    turned[0] += turn;
    out.push_back(turned);
  }
  out.push_back(upright);
  for (const double turn : kTurns) {
    JointVector q = upright;
    q[0] += turn;
    out.push_back(q);
  }
  return out;
}

bool withinLimits(const RobotModel& model, const JointVector& q) {
  for (int i = 0; i < q.size(); ++i)
    if (q[i] < model.limits.position_min[i] || q[i] > model.limits.position_max[i]) return false;
  return true;
}
}  // namespace

JointVector parkingConfiguration(const CollisionWorld& world, CollisionContext& context, int robot,
                                 const HeldObject& held, const std::vector<RobotState>& keep_clear_of,
                                 const ObjectLayout& layout) {
  const SceneRobot& r = world.scene().robots[robot];
  for (const JointVector& q : candidatesFor(r)) {
    if (!withinLimits(*r.model, q)) continue;
    const RobotState self{robot, q, held};
    if (robotInCollision(world, context, self, layout)) continue;
    bool clear = true;
    for (const RobotState& other : keep_clear_of) {
      const RobotState pair[2] = {self, other};
      if (robotsInCollision(world, context, pair, layout, nullptr, CheckScope::kStaticOnly)) {
        clear = false;
        break;
      }
    }
    if (clear) return q;
  }
  return r.home;
}

}  // namespace dash
