#include "engine/scenarios/scene_builder.h"

#include <cmath>

#include "engine/core/check.h"

namespace dash {

namespace {

// Steps per metre and per unit quaternion component. Dividing the rounded integer by the scale (not
// multiplying by its inverse) gives the double nearest to the decimal, which prints short.
constexpr double kLengthScale = 1e6;
constexpr double kQuaternionScale = 1e9;

double roundTo(double x, double scale) {
  const double r = std::round(x * scale) / scale;
  return r == 0.0 ? 0.0 : r;  // no "-0"
}

Vec3 roundVec(const Vec3& v) { return Vec3(roundLength(v.x()), roundLength(v.y()), roundLength(v.z())); }

}  // namespace

double roundLength(double x) { return roundTo(x, kLengthScale); }

Pose yawPose(const Vec3& p, double yaw) {
  const double qz = roundTo(std::sin(0.5 * yaw), kQuaternionScale);
  const double qw = roundTo(std::cos(0.5 * yaw), kQuaternionScale);
  return makePose(roundVec(p), Quat(qw, 0.0, 0.0, qz));
}

Eigen::Vector2d rotate2(const Eigen::Vector2d& v, double yaw) {
  const double c = std::cos(yaw);
  const double s = std::sin(yaw);
  return Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
}

SceneBuilder::SceneBuilder(std::shared_ptr<const RobotLibrary> library, std::string name, SceneGenerator generator) {
  DASH_DEMAND(library != nullptr);
  scene_.name = std::move(name);
  scene_.generator = std::move(generator);
  scene_.library = std::move(library);
}

void SceneBuilder::addRobot(const std::string& id, const std::string& model, const Vec3& p, double yaw,
                            const std::vector<double>& home, std::vector<std::string> capabilities) {
  SceneRobot r;
  r.id = id;
  r.model_name = model;
  r.model = &scene_.library->get(model);
  DASH_DEMAND(static_cast<int>(home.size()) == r.model->dof());
  r.X_WB = yawPose(p, yaw);
  r.home = JointVector::Map(home.data(), static_cast<Eigen::Index>(home.size()));
  r.capabilities = std::move(capabilities);
  scene_.robots.push_back(std::move(r));
}

void SceneBuilder::addBox(const std::string& id, const Vec3& size, const Vec3& center, double yaw) {
  scene_.obstacles.push_back(
      SceneObstacle{.id = id, .shape = BoxShape{.size = roundVec(size)}, .X_WO = yawPose(center, yaw)});
}

void SceneBuilder::addSurface(const std::string& id, double z, const std::vector<Eigen::Vector2d>& polygon) {
  SceneSurface s;
  s.id = id;
  s.z = roundLength(z);
  for (const auto& xy : polygon) s.polygon.emplace_back(roundLength(xy.x()), roundLength(xy.y()));
  scene_.surfaces.push_back(std::move(s));
}

void SceneBuilder::addRectSurface(const std::string& id, double z, const Eigen::Vector2d& center,
                                  const Eigen::Vector2d& size, double yaw) {
  const Eigen::Vector2d h = 0.5 * size;
  std::vector<Eigen::Vector2d> corners;
  for (const auto& c : {Eigen::Vector2d(-h.x(), -h.y()), Eigen::Vector2d(h.x(), -h.y()), Eigen::Vector2d(h.x(), h.y()),
                        Eigen::Vector2d(-h.x(), h.y())}) {
    corners.push_back(center + rotate2(c, yaw));
  }
  addSurface(id, z, corners);
}

int SceneBuilder::addObject(const std::string& id, const Vec3& size, const Pose& start, const std::optional<Pose>& goal,
                            bool fixed) {
  SceneObject o;
  o.id = id;
  o.shape = BoxShape{.size = roundVec(size)};
  o.X_WO_start = start;
  o.X_WO_goal = goal;
  o.fixed = fixed;
  scene_.objects.push_back(std::move(o));
  return static_cast<int>(scene_.objects.size()) - 1;
}

void SceneBuilder::addInspectTask(const std::string& target, const Pose& X_WT, const std::string& requires_removed,
                                  const std::string& capability) {
  SceneTask t;
  t.type = SceneTask::Type::kInspect;
  t.target = target;
  t.X_WT = X_WT;
  t.requires_removed = requires_removed;
  t.capability = capability;
  scene_.tasks.push_back(std::move(t));
}

Scene SceneBuilder::build() {
  for (SceneTask& t : scene_.tasks) {
    t.target_object = scene_.objectIndex(t.target);
    DASH_DEMAND(t.target_object >= 0);
    if (t.requires_removed) {
      t.requires_removed_object = scene_.objectIndex(*t.requires_removed);
      DASH_DEMAND(t.requires_removed_object >= 0);
    }
  }
  return std::move(scene_);
}

}  // namespace dash
