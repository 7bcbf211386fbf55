#include "engine/task/move_out_sampler.h"

#include "engine/collision/collision_queries.h"

namespace dash {

namespace {
constexpr double kMoveOutRadius = 0.75;   // around the robot base that will move the object out
constexpr double kMoveOutSpacing = 0.09;  // centre distance to every other known object location
constexpr int kMoveOutAttempts = 400;     // samples per robot and pass
}  // namespace

MoveOutSampler::MoveOutSampler(const TaskSpace& space, TransitionSampler& sampler,
                               GeometricReachability& reachability, const TaskConflictParams& grasps, bool one_grasp)
    : space_(&space), sampler_(&sampler), reachability_(&reachability), grasps_(grasps), one_grasp_(one_grasp) {
  for (const SceneSurface& s : space.scene().surfaces) regions_.emplace_back(s);
}

std::optional<MoveOutPose> MoveOutSampler::forExpansion(int object, Rng& rng) const {
  return search(object, {Rule{true, true}, Rule{false, true}, Rule{false, false}}, rng);
}

std::optional<MoveOutPose> MoveOutSampler::forResample(int object, Rng& rng) const {
  if (!one_grasp_) return std::nullopt;
  return search(object, {Rule{true, true}, Rule{true, false}}, rng);
}

std::optional<MoveOutPose> MoveOutSampler::search(int object, const std::vector<Rule>& rules, Rng& rng) const {
  const std::vector<int> robots = takers(object);
  for (const Rule& rule : rules) {
    if (rule.one_grasp && !one_grasp_) continue;
    for (int attempt = 0; attempt < kMoveOutAttempts; ++attempt)
      for (int r : robots)
        if (auto found = sample(object, r, rule, robots, rng)) return found;
  }
  return std::nullopt;
}

std::vector<int> MoveOutSampler::takers(int object) const {
  const Scene& scene = space_->scene();
  const Pose& start = space_->location(object, space_->startLocation(object)).X_WO;
  std::vector<int> robots;
  for (int r = 0; r < static_cast<int>(scene.robots.size()); ++r)
    if (scene.robots[r].hasCapability("grasp") && graspsAt(r, object, start)) robots.push_back(r);
  return robots;
}

// One sample on a random support surface (near the base of an arm), kept if it passes `rule`.
std::optional<MoveOutPose> MoveOutSampler::sample(int object, int r, Rule rule, const std::vector<int>& takers,
                                                  Rng& rng) const {
  const Scene& scene = space_->scene();
  const SceneObject& obj = scene.objects[object];
  const int s = static_cast<int>(rng.integer(0, static_cast<std::int64_t>(regions_.size()) - 1));
  const bool arm = scene.robots[r].model->kinematics == KinematicsKind::kUrDh;
  const auto pose = arm ? regions_[s].sampleNear(obj.shape, scene.robots[r].X_WB.translation(), kMoveOutRadius, rng, 4)
                        : regions_[s].sample(obj.shape, rng, 4);
  if (!pose) return std::nullopt;
  for (int o = 0; o < space_->objectCount(); ++o)
    for (const ObjectLocation& l : space_->locations(o))
      if ((rule.clear_of_extras || !l.resampleable) && (l.X_WO.translation() - pose->translation()).norm() < kMoveOutSpacing)
        return std::nullopt;
  if (objectInCollision(sampler_->world(), sampler_->context(), object, *pose, ObjectLayout::empty(scene)))
    return std::nullopt;
  if (!graspsAt(r, object, *pose)) return std::nullopt;
  if (rule.one_grasp && !trapsNoTaker(object, takers, *pose)) return std::nullopt;
  return MoveOutPose{*pose, s};
}

// Both ways: a robot offered the pose carries the object there from its start with one grasp, and from
// there to its goal (where it can grasp it at the goal) with one grasp.
bool MoveOutSampler::trapsNoTaker(int object, const std::vector<int>& takers, const Pose& X_WO) const {
  const Pose& start = space_->location(object, space_->startLocation(object)).X_WO;
  const int goal_location = space_->goalLocation(object);
  for (int r : takers) {
    if (!graspsAt(r, object, X_WO)) continue;
    if (!carriesWithOneGrasp(r, object, start, X_WO)) return false;
    if (goal_location < 0) continue;
    const Pose& goal = space_->location(object, goal_location).X_WO;
    if (graspsAt(r, object, goal) && !carriesWithOneGrasp(r, object, X_WO, goal)) return false;
  }
  return true;
}

bool MoveOutSampler::graspsAt(int robot, int object, const Pose& X_WO) const {
  return reachability_->canGrasp(robot, object, X_WO, GraspClass::kTop) ||
         reachability_->canGrasp(robot, object, X_WO, GraspClass::kSide);
}

// Some grasp that the robot can take at `from` (the grasps task conflict detection tries) also holds
// the object, statically free, at `to`.
bool MoveOutSampler::carriesWithOneGrasp(int robot, int object, const Pose& from, const Pose& to) const {
  for (GraspClass g : {GraspClass::kTop, GraspClass::kSide})
    for (const GraspConfig& gc :
         sampler_->graspConfigs(robot, object, from, g, grasps_.grasp_candidates, grasps_.prefer_free_approach))
      if (!sampler_->holdConfigs(robot, object, to, gc.X_TO, 1).empty()) return true;
  return false;
}

}  // namespace dash
