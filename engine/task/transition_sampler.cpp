#include "engine/task/transition_sampler.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "engine/collision/collision_queries.h"
#include "engine/collision/segment_queries.h"
#include "engine/robots/kinematics.h"

namespace dash {

namespace {
constexpr double kTopBottomCosine = 0.7;      // |cos| of the approach against vertical
constexpr double kApproachLine = 0.2;         // metres a side grasp at a pick or place should back off straight
constexpr double kUrReachMetres = 1.05;       // TCP from the base axis, generous (0.85 flange + TCP offset)
// Handover search grid (as the scenario generators' handover graph): heights above the higher base,
// offsets along the base-to-base line and across it (round the end of a panel or shelf).
constexpr double kHandoverHeights[] = {0.35, 0.25, 0.45, 0.6};
// Across offsets reach round the end of a divider (shelf-wall), as the generators' handover search does.
constexpr double kHandoverAcross[] = {0.0, -0.15, 0.15, -0.3, 0.3, -0.45, 0.45, -0.55, 0.55, -0.65, 0.65, -0.75, 0.75};
constexpr double kHandoverAlong[] = {0.0, -0.1, 0.1, -0.2, 0.2};
constexpr double kHandoverYaws[] = {0.0, 1.5707963267948966, 3.141592653589793, -1.5707963267948966};

double jointDistance(const JointVector& a, const JointVector& b) { return (a - b).cwiseAbs().sum(); }

constexpr std::size_t kMaxMemoEntries = 50000;  // per kind; cleared when full (under 100 MB)

/// The exact bytes of the arguments, as a hash key.
std::string memoKey(int robot, int object, const Pose& X_WO, int what, const Pose& X_TO, int limit, bool approach) {
  std::string key;
  auto put = [&](const void* p, std::size_t n) { key.append(static_cast<const char*>(p), n); };
  const int ints[] = {robot, object, what, limit, approach ? 1 : 0};
  put(ints, sizeof ints);
  put(X_WO.matrix().data(), 16 * sizeof(double));
  put(X_TO.matrix().data(), 16 * sizeof(double));
  return key;
}

template <typename Map, typename Compute>
const typename Map::mapped_type& remembered(Map& memo, std::string key, Compute compute) {
  if (auto it = memo.find(key); it != memo.end()) return it->second;
  if (memo.size() >= kMaxMemoEntries) memo.clear();
  return memo.emplace(std::move(key), compute()).first->second;
}
}  // namespace

GraspClass classifyGrasp(const Pose& X_WT) {
  const double z = X_WT.linear().col(2).z();
  if (z < -kTopBottomCosine) return GraspClass::kTop;
  if (z > kTopBottomCosine) return GraspClass::kBottom;
  return GraspClass::kSide;
}

TransitionSampler::TransitionSampler(const CollisionWorld& world, CollisionContext& context)
    : world_(&world), context_(&context), no_objects_(ObjectLayout::empty(world.scene())) {}

bool TransitionSampler::inRange(int robot, const Vec3& p_W) const {
  const SceneRobot& r = world_->scene().robots[robot];
  if (r.model->kinematics == KinematicsKind::kGantry) {
    const Vec3 p_B = r.X_WB.inverse() * p_W;
    const auto& lo = r.model->limits.position_min;
    const auto& hi = r.model->limits.position_max;
    return p_B.x() >= lo[0] - 1e-6 && p_B.x() <= hi[0] + 1e-6 && p_B.y() >= lo[1] - 1e-6 && p_B.y() <= hi[1] + 1e-6;
  }
  return (p_W - r.X_WB.translation()).norm() < kUrReachMetres + 0.2;
}

std::vector<JointVector> TransitionSampler::ikSolutions(int robot, const Pose& X_WT) const {
  const SceneRobot& r = world_->scene().robots[robot];
  std::vector<JointVector> solutions = inverseKinematics(*r.model, r.X_WB, X_WT);
  std::stable_sort(solutions.begin(), solutions.end(), [&](const JointVector& a, const JointVector& b) {
    return jointDistance(a, r.home) < jointDistance(b, r.home);
  });
  return solutions;
}

bool TransitionSampler::staticFree(const RobotState& state) {
  return !robotInCollision(*world_, *context_, state, no_objects_, nullptr, CheckScope::kStaticOnly);
}

std::vector<GraspConfig> TransitionSampler::graspConfigs(int robot, int object, const Pose& X_WO, GraspClass g,
                                                         int limit, bool approach) {
  return remembered(grasp_memo_, memoKey(robot, object, X_WO, static_cast<int>(g), Pose::Identity(), limit, approach),
                    [&] { return computeGraspConfigs(robot, object, X_WO, g, limit, approach); });
}

std::vector<JointVector> TransitionSampler::holdConfigs(int robot, int object, const Pose& X_WO, const Pose& X_TO,
                                                        int limit, bool approach) {
  return remembered(hold_memo_, memoKey(robot, object, X_WO, -1, X_TO, limit, approach),
                    [&] { return computeHoldConfigs(robot, object, X_WO, X_TO, limit, approach); });
}

std::vector<GraspConfig> TransitionSampler::computeGraspConfigs(int robot, int object, const Pose& X_WO, GraspClass g,
                                                                int limit, bool approach) {
  std::vector<GraspConfig> out;
  if (!inRange(robot, X_WO.translation())) return out;
  const SceneRobot& r = world_->scene().robots[robot];
  const BoxShape& box = world_->scene().objects[object].shape;
  for (const GraspCandidate& c : graspCandidates(*r.model, r.X_WB, box, X_WO)) {
    if (classifyGrasp(c.X_WT) != g) continue;
    // One configuration per candidate: the one closest to home (with a free approach line if asked).
    const HeldObject held{object, c.X_TO};
    const bool check_line = approach && g == GraspClass::kSide;
    std::optional<JointVector> chosen, fallback;
    for (const JointVector& q : ikSolutions(robot, c.X_WT)) {
      if (!staticFree({robot, q, held})) continue;
      if (!fallback) fallback = q;
      if (!check_line || approachLineFree(robot, q, held, kApproachLine)) {
        chosen = q;
        break;
      }
    }
    if (chosen || fallback) out.push_back({chosen ? *chosen : *fallback, c.X_TO, c.face});
    if (static_cast<int>(out.size()) >= limit) break;
  }
  return out;
}

std::vector<JointVector> TransitionSampler::computeHoldConfigs(int robot, int object, const Pose& X_WO,
                                                               const Pose& X_TO, int limit, bool approach) {
  std::vector<JointVector> out, blocked_line;
  if (!inRange(robot, X_WO.translation())) return out;
  const Pose X_WT = X_WO * X_TO.inverse();
  const bool check_line = approach && classifyGrasp(X_WT) == GraspClass::kSide;
  const HeldObject held{object, X_TO};
  for (const JointVector& q : ikSolutions(robot, X_WT)) {
    if (!staticFree({robot, q, held})) continue;
    (!check_line || approachLineFree(robot, q, held, kApproachLine) ? out : blocked_line).push_back(q);
    if (static_cast<int>(out.size()) >= limit) break;
  }
  for (const JointVector& q : blocked_line)
    if (static_cast<int>(out.size()) < limit) out.push_back(q);
  return out;
}

bool TransitionSampler::approachLineFree(int robot, const JointVector& q, const HeldObject& held, double distance) {
  constexpr double kStep = 0.01;          // metres between IK waypoints
  constexpr double kMaxJointStep = 0.35;  // radians per joint between waypoints: more is a branch flip
  const SceneRobot& r = world_->scene().robots[robot];
  if (r.model->kinematics != KinematicsKind::kUrDh) return true;  // a gantry moves its TCP in lines
  const Pose X_WT = forwardKinematics(*r.model, r.X_WB, q).X_WT;
  const Vec3 back = -X_WT.linear().col(2);
  const int n = std::max(1, static_cast<int>(std::ceil(distance / kStep)));
  JointVector prev = q;
  for (int i = 1; i <= n; ++i) {
    const Pose X_WTi = makePose(back * (distance * i / n)) * X_WT;
    std::optional<JointVector> next;
    for (const JointVector& cand : inverseKinematics(*r.model, r.X_WB, X_WTi))
      if (!next || (cand - prev).cwiseAbs().maxCoeff() < (*next - prev).cwiseAbs().maxCoeff()) next = cand;
    if (!next || (*next - prev).cwiseAbs().maxCoeff() > kMaxJointStep) return false;
    if (segmentInCollision(*world_, *context_, {robot, prev, held}, *next, no_objects_, nullptr,
                           {CheckScope::kStaticOnly}))
      return false;
    prev = *next;
  }
  return true;
}

std::vector<int> TransitionSampler::blockingObjects(const RobotState& state, ObjectLayout layout) {
  std::vector<int> blockers;
  for (int guard = 0; guard < layout.size(); ++guard) {
    CollisionReport report;
    if (!robotInCollision(*world_, *context_, state, layout, &report, CheckScope::kObjectsOnly)) break;
    const int j = report.b.kind == CollisionElement::Kind::kObject ? report.b.index
                  : report.a.kind == CollisionElement::Kind::kObject ? report.a.index
                                                                       : -1;
    if (j < 0 || !layout.isPresent(j)) break;
    blockers.push_back(j);
    layout.remove(j);
  }
  return blockers;
}

std::vector<Pose> TransitionSampler::handoverPoses(int giver, int receiver) const {
  const Scene& scene = world_->scene();
  const Vec3 a = scene.robots[giver].X_WB.translation();
  const Vec3 b = scene.robots[receiver].X_WB.translation();
  Vec3 along = b - a;
  along.z() = 0.0;
  const double yaw = std::atan2(along.y(), along.x());
  const Vec3 lateral = Vec3(-std::sin(yaw), std::cos(yaw), 0.0);
  const Vec3 mid = 0.5 * (a + b);
  const double base_z = std::max(a.z(), b.z());
  std::vector<Pose> poses;
  // Every quarter-turn of the object at one spot before moving the spot: a grasp fixed earlier may
  // face either robot depending on the object's yaw.
  const Vec3 forward(std::cos(yaw), std::sin(yaw), 0.0);
  for (double h : kHandoverHeights)
    for (double across : kHandoverAcross)
      for (double along_offset : kHandoverAlong)
        for (double dyaw : kHandoverYaws) {
          const Vec3 q = mid + along_offset * forward + across * lateral;
          const Vec3 p(q.x(), q.y(), base_z + h);
          if (!inRange(giver, p) || !inRange(receiver, p)) continue;
          poses.push_back(makePose(p, Quat(Eigen::AngleAxisd(yaw + dyaw, Vec3::UnitZ()))));
        }
  return poses;
}

}  // namespace dash
