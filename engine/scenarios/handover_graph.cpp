#include "engine/scenarios/handover_graph.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>

#include "engine/collision/collision_queries.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {

inline std::size_t at(int i) { return static_cast<std::size_t>(i); }

/// Pair checks tried at one object position before moving on (bounds the cost of hopeless pairs).
constexpr int kMaxPairChecksPerPose = 400;

struct HeldGrasp {
  GraspCandidate grasp;
  JointVector q;
};

/// Every (grasp, IK solution) with which robot r holds `object` at X_WO without touching obstacles or
/// itself (no resting objects).
std::vector<HeldGrasp> collisionFreeGrasps(const CollisionWorld& world, CollisionContext& context, int r, int object,
                                           const Pose& X_WO, const ObjectLayout& layout, bool first_only) {
  std::vector<HeldGrasp> out;
  const SceneRobot& robot = world.scene().robots[at(r)];
  const BoxShape& shape = world.scene().objects[at(object)].shape;
  for (const GraspCandidate& c : graspCandidates(*robot.model, robot.X_WB, shape, X_WO)) {
    for (const JointVector& q : inverseKinematics(*robot.model, robot.X_WB, c.X_WT)) {
      const RobotState state{.robot = r, .q = q, .held = {.object = object, .X_TO = c.X_TO}};
      if (robotInCollision(world, context, state, layout)) continue;
      out.push_back({c, q});
      if (first_only) return out;
    }
  }
  return out;
}

bool withinReach(const SceneRobot& robot, const Vec3& p_W, double margin) {
  return (p_W - robot.X_WB.translation()).norm() <= maxTcpReach(*robot.model) + margin;
}

}  // namespace

double maxTcpReach(const RobotModel& model) {
  if (model.kinematics == KinematicsKind::kUrDh) {
    double sum = model.dh.X_FT.translation().norm();
    for (int i = 0; i < 6; ++i) sum += std::abs(model.dh.a[at(i)]) + std::abs(model.dh.d[at(i)]);
    return sum;
  }
  const JointVector span = model.limits.position_max - model.limits.position_min;
  return span.norm() + model.gantry.beam_height;
}

std::optional<HandoverPose> findHandover(const CollisionWorld& world, CollisionContext& context, int r1, int r2,
                                         int object, const HandoverSearch& search) {
  const Scene& scene = world.scene();
  const SceneRobot& a = scene.robots[at(r1)];
  const SceneRobot& b = scene.robots[at(r2)];
  const Vec3 p_a = a.X_WB.translation();
  const Vec3 p_b = b.X_WB.translation();
  Vec3 along = p_b - p_a;
  along.z() = 0.0;
  if (along.norm() < 1e-9) return std::nullopt;
  if (along.norm() > maxTcpReach(*a.model) + maxTcpReach(*b.model)) return std::nullopt;
  along.normalize();
  const Vec3 across(-along.y(), along.x(), 0.0);
  const double yaw = std::atan2(along.y(), along.x());
  const Vec3 mid(0.5 * (p_a.x() + p_b.x()), 0.5 * (p_a.y() + p_b.y()), std::max(p_a.z(), p_b.z()));
  const ObjectLayout free_space = ObjectLayout::empty(scene);

  for (const double h : search.heights) {
    for (const double u : search.along) {
      for (const double v : search.across) {
        const Vec3 p = mid + u * along + v * across + Vec3(0.0, 0.0, h);
        if (!withinReach(a, p, 0.0) || !withinReach(b, p, 0.0)) continue;
        const Pose X_WO = makePose(p, Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ())));
        const std::vector<HeldGrasp> ga = collisionFreeGrasps(world, context, r1, object, X_WO, free_space, false);
        if (ga.empty()) continue;
        const std::vector<HeldGrasp> gb = collisionFreeGrasps(world, context, r2, object, X_WO, free_space, false);
        if (gb.empty()) continue;
        int checks = 0;
        for (const HeldGrasp& x : ga) {
          for (const HeldGrasp& y : gb) {
            if (++checks > kMaxPairChecksPerPose) break;
            const std::array<RobotState, 2> states{
                RobotState{.robot = r1, .q = x.q, .held = {.object = object, .X_TO = x.grasp.X_TO}},
                RobotState{.robot = r2, .q = y.q, .held = {.object = object, .X_TO = y.grasp.X_TO}}};
            if (robotsInCollision(world, context, states, free_space)) continue;
            return HandoverPose{.giver = r1,
                                .receiver = r2,
                                .X_WO = X_WO,
                                .giver_grasp = x.grasp,
                                .receiver_grasp = y.grasp,
                                .q_giver = x.q,
                                .q_receiver = y.q};
          }
          if (checks > kMaxPairChecksPerPose) break;
        }
      }
    }
  }
  return std::nullopt;
}

bool HandoverGraph::linked(int r1, int r2) const {
  const auto& n = adjacent[at(r1)];
  return std::binary_search(n.begin(), n.end(), r2);
}

HandoverGraph buildHandoverGraph(const CollisionWorld& world, CollisionContext& context, int object,
                                 const HandoverSearch& search) {
  const Scene& scene = world.scene();
  HandoverGraph graph;
  graph.adjacent.resize(scene.robots.size());
  for (int r1 = 0; r1 < world.robotCount(); ++r1) {
    if (!scene.robots[at(r1)].hasCapability("grasp")) continue;
    for (int r2 = r1 + 1; r2 < world.robotCount(); ++r2) {
      if (!scene.robots[at(r2)].hasCapability("grasp")) continue;
      if (auto h = findHandover(world, context, r1, r2, object, search)) {
        graph.adjacent[at(r1)].push_back(r2);
        graph.adjacent[at(r2)].push_back(r1);
        graph.edges.push_back(*h);
      }
    }
  }
  for (auto& n : graph.adjacent) std::sort(n.begin(), n.end());
  return graph;
}

std::vector<int> robotsAbleToGrasp(const CollisionWorld& world, CollisionContext& context, int object, const Pose& X_WO,
                                   const ObjectLayout& layout) {
  std::vector<int> out;
  const Scene& scene = world.scene();
  for (int r = 0; r < world.robotCount(); ++r) {
    const SceneRobot& robot = scene.robots[at(r)];
    if (!robot.hasCapability("grasp")) continue;
    if (!withinReach(robot, X_WO.translation(), 0.05)) continue;
    if (!collisionFreeGrasps(world, context, r, object, X_WO, layout, true).empty()) out.push_back(r);
  }
  return out;
}

int minHandovers(const HandoverGraph& graph, const std::vector<int>& from, const std::vector<int>& to) {
  std::vector<int> distance(graph.adjacent.size(), -1);
  std::deque<int> queue;
  for (const int r : from) {
    if (distance[at(r)] == 0) continue;
    distance[at(r)] = 0;
    queue.push_back(r);
  }
  while (!queue.empty()) {
    const int r = queue.front();
    queue.pop_front();
    if (std::find(to.begin(), to.end(), r) != to.end()) return distance[at(r)];
    for (const int n : graph.adjacent[at(r)]) {
      if (distance[at(n)] >= 0) continue;
      distance[at(n)] = distance[at(r)] + 1;
      queue.push_back(n);
    }
  }
  return -1;
}

}  // namespace dash
