#include "engine/robots/robot_model.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "engine/core/check.h"
#include "engine/core/json_parse.h"
#include "engine/core/json_reader.h"
#include "engine/core/paths.h"
#include "engine/geometry/pose_json.h"

namespace dash {

namespace {

using nlohmann::json;

constexpr const char* kFormat = "dashbench.robot/1";
constexpr int kUrJoints = 6;
constexpr int kGantryJoints = 3;
constexpr double kSnapEps = 1e-15;       // cos/sin of alpha this close to 0 or +-1 are exact
constexpr double kUrStructureTol = 1e-9;  // the analytic IK needs the UR DH structure to this

std::string indexed(const std::string& path, std::size_t i) { return jsonPathIndex(path, i); }

/// The shared field reader plus what robot models add: vectors, poses and optional fields.
class Reader : public JsonReader<json> {
 public:
  explicit Reader(const std::string& source) : JsonReader<json>(source, "robot model") {}

  /// The value of `key` in `obj`, or nullptr.
  const json* optionalField(const json& obj, const char* key) const {
    auto it = obj.find(key);
    return it == obj.end() ? nullptr : &*it;
  }
  Vec3 vec3(const json& j, const std::string& path) const {
    const auto v = numbers(j, path, 3);
    return Vec3(v[0], v[1], v[2]);
  }
  Pose pose(const json& j, const std::string& path) const { return readPose(*this, j, path); }
};

JointVector toJointVector(const std::vector<double>& v) {
  JointVector q(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) q[static_cast<Eigen::Index>(i)] = v[i];
  return q;
}

void parseUrKinematics(const Reader& r, const json& kin, RobotModel& m) {
  const auto a = r.numbers(r.field(kin, "kinematics", "a"), "kinematics.a", kUrJoints);
  const auto d = r.numbers(r.field(kin, "kinematics", "d"), "kinematics.d", kUrJoints);
  const auto alpha = r.numbers(r.field(kin, "kinematics", "alpha"), "kinematics.alpha", kUrJoints);
  std::copy(a.begin(), a.end(), m.dh.a.begin());
  std::copy(d.begin(), d.end(), m.dh.d.begin());
  std::copy(alpha.begin(), alpha.end(), m.dh.alpha.begin());
  m.dh.X_FT = r.pose(r.field(kin, "kinematics", "tcp_in_flange"), "kinematics.tcp_in_flange");
  m.dh.updateDerived();

  // The closed-form IK (kinematics.cpp) is the one for UR arms: three parallel middle axes
  // (alpha = [pi/2, 0, 0, pi/2, -pi/2, 0]) and no link lengths outside the two arm links.
  const double half_pi = M_PI / 2;
  const std::array<double, 6> ur_alpha{half_pi, 0.0, 0.0, half_pi, -half_pi, 0.0};
  for (int i = 0; i < kUrJoints; ++i) {
    if (std::abs(alpha[i] - ur_alpha[i]) > kUrStructureTol) {
      r.fail(indexed("kinematics.alpha", static_cast<std::size_t>(i)),
             "must be [pi/2, 0, 0, pi/2, -pi/2, 0] (UR arm structure)");
    }
  }
  for (int i : {0, 3, 4, 5}) {
    if (a[i] != 0.0) r.fail(indexed("kinematics.a", static_cast<std::size_t>(i)), "must be 0 (UR arm structure)");
  }
  for (int i : {1, 2}) {
    if (d[i] != 0.0) r.fail(indexed("kinematics.d", static_cast<std::size_t>(i)), "must be 0 (UR arm structure)");
  }
  if (a[1] == 0.0 || a[2] == 0.0) r.fail("kinematics.a", "a[1] and a[2] must be non-zero");
  if (d[3] == 0.0) r.fail("kinematics.d[3]", "must be non-zero (UR arm structure)");
}

void parseGantryKinematics(const Reader& r, const json& kin, RobotModel& m) {
  m.gantry.beam_height = r.number(r.field(kin, "kinematics", "beam_height"), "kinematics.beam_height");
  m.gantry.ram_to_tcp = r.number(r.field(kin, "kinematics", "ram_to_tcp"), "kinematics.ram_to_tcp");
}

void parseLimits(const Reader& r, const json& doc, RobotModel& m) {
  const json& lim = r.field(doc, "", "limits");
  const auto n = static_cast<std::size_t>(m.dof());
  m.limits.position_min = toJointVector(r.numbers(r.field(lim, "limits", "position_min"), "limits.position_min", n));
  m.limits.position_max = toJointVector(r.numbers(r.field(lim, "limits", "position_max"), "limits.position_max", n));
  m.limits.velocity_max = toJointVector(r.numbers(r.field(lim, "limits", "velocity_max"), "limits.velocity_max", n));
  for (int i = 0; i < m.dof(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    if (m.limits.position_min[i] > m.limits.position_max[i]) {
      r.fail(indexed("limits.position_min", k), "is greater than " + indexed("limits.position_max", k));
    }
    if (m.limits.velocity_max[i] <= 0.0) r.fail(indexed("limits.velocity_max", k), "must be positive");
  }
}

CollisionBody parseBody(const Reader& r, const json& b, const std::string& path, const RobotModel& m) {
  CollisionBody body;
  body.name = r.string(r.field(b, path, "name"), path + ".name");
  if (body.name.empty()) r.fail(path + ".name", "must not be empty");
  const bool ur = m.kinematics == KinematicsKind::kUrDh;

  if (const json* f = r.optionalField(b, "frame")) {
    if (!f->is_number_integer()) r.fail(path + ".frame", "expected an integer frame index");
    const long long frame = f->get<long long>();
    const int max_frame = ur ? kUrJoints : 0;
    if (frame < 0 || frame > max_frame) {
      r.fail(path + ".frame", "unknown body frame " + std::to_string(frame) + " (valid: 0.." +
                                  std::to_string(max_frame) + ")");
    }
    body.frame = static_cast<int>(frame);
  } else if (ur) {
    r.fail(path + ".frame", "missing field");
  }

  if (const json* mv = r.optionalField(b, "moves")) {
    if (ur) r.fail(path + ".moves", "only gantry bodies move with axes");
    r.array(*mv, path + ".moves");
    for (std::size_t i = 0; i < mv->size(); ++i) {
      const std::string item_path = indexed(path + ".moves", i);
      const std::string axis = r.string((*mv)[i], item_path);
      if (axis != "x" && axis != "y" && axis != "z") r.fail(item_path, "expected \"x\", \"y\" or \"z\"");
      const auto k = static_cast<std::size_t>(axis[0] - 'x');
      if (body.moves[k]) r.fail(item_path, "axis listed twice");
      body.moves[k] = true;
    }
  } else if (!ur) {
    r.fail(path + ".moves", "missing field");
  }

  const json* capsule = r.optionalField(b, "capsule");
  const json* box = r.optionalField(b, "box");
  if ((capsule == nullptr) == (box == nullptr)) r.fail(path, "needs exactly one of \"capsule\" or \"box\"");
  if (!ur && capsule != nullptr) r.fail(path + ".capsule", "gantry bodies must be boxes");
  if (capsule != nullptr) {
    const std::string cp = path + ".capsule";
    body.kind = CollisionBody::Kind::kCapsule;
    body.capsule.a = r.vec3(r.field(*capsule, cp, "a"), cp + ".a");
    body.capsule.b = r.vec3(r.field(*capsule, cp, "b"), cp + ".b");
    body.capsule.radius = r.number(r.field(*capsule, cp, "radius"), cp + ".radius");
    if (body.capsule.radius <= 0.0) r.fail(cp + ".radius", "must be positive");
  } else {
    const std::string bp = path + ".box";
    body.kind = CollisionBody::Kind::kBox;
    body.box_center = r.vec3(r.field(*box, bp, "center"), bp + ".center");
    body.box_half_extents = r.vec3(r.field(*box, bp, "half_extents"), bp + ".half_extents");
    if ((body.box_half_extents.array() <= 0.0).any()) r.fail(bp + ".half_extents", "must be positive");
    if (!ur) {
      // The gantry body frame is the moved box centre (see CollisionBody), so the centre in it is 0.
      body.gantry_base_center = body.box_center;
      body.box_center = Vec3::Zero();
    }
  }

  // Gripper bodies are the ones rigid with the TCP (UR: mounted on the flange, frame 6; gantry:
  // moving with all three axes). An object held at the TCP keeps a fixed pose relative to them, so
  // they never count against it. An explicit "gripper": true/false overrides the rule.
  body.is_gripper = ur ? body.frame == kUrJoints : (body.moves[0] && body.moves[1] && body.moves[2]);
  if (const json* g = r.optionalField(b, "gripper")) {
    if (!g->is_boolean()) r.fail(path + ".gripper", "expected true or false");
    body.is_gripper = g->get<bool>();
  }
  return body;
}

void parseCollision(const Reader& r, const json& doc, RobotModel& m) {
  const json& col = r.field(doc, "", "collision");
  const json& bodies = r.array(r.field(col, "collision", "bodies"), "collision.bodies");
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string path = indexed("collision.bodies", i);
    CollisionBody body = parseBody(r, bodies[i], path, m);
    if (m.bodyIndex(body.name) >= 0) r.fail(path + ".name", "duplicate body name '" + body.name + "'");
    m.bodies.push_back(std::move(body));
  }
  const json& pairs = r.array(r.field(col, "collision", "self_collision_pairs"), "collision.self_collision_pairs");
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    const std::string path = indexed("collision.self_collision_pairs", i);
    r.array(pairs[i], path);
    if (pairs[i].size() != 2) r.fail(path, "expected 2 body names, got " + std::to_string(pairs[i].size()));
    std::array<int, 2> idx{};
    for (std::size_t k = 0; k < 2; ++k) {
      const std::string item_path = indexed(path, k);
      const std::string name = r.string(pairs[i][k], item_path);
      idx[k] = m.bodyIndex(name);
      if (idx[k] < 0) r.fail(item_path, "unknown body '" + name + "'");
    }
    if (idx[0] == idx[1]) r.fail(path, "a body cannot be paired with itself");
    m.self_collision_pairs.emplace_back(idx[0], idx[1]);
  }
}

}  // namespace

void DhParameters::updateDerived() {
  for (std::size_t i = 0; i < alpha.size(); ++i) {
    double c = std::cos(alpha[i]);
    double s = std::sin(alpha[i]);
    auto snap = [](double& v) {
      if (std::abs(v) < kSnapEps) v = 0.0;
      if (std::abs(v - 1.0) < kSnapEps) v = 1.0;
      if (std::abs(v + 1.0) < kSnapEps) v = -1.0;
    };
    snap(c);
    snap(s);
    cos_alpha[i] = c;
    sin_alpha[i] = s;
  }
}

int RobotModel::bodyIndex(const std::string& body_name) const {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    if (bodies[i].name == body_name) return static_cast<int>(i);
  }
  return -1;
}

bool RobotModel::withinLimits(const JointVector& q, double tolerance) const {
  if (q.size() != dof()) return false;
  for (int i = 0; i < dof(); ++i) {
    if (!(q[i] >= limits.position_min[i] - tolerance && q[i] <= limits.position_max[i] + tolerance)) {
      return false;  // also catches NaN
    }
  }
  return true;
}

RobotModel parseRobotModel(const std::string& json_text, const std::string& source_name) {
  const Reader r(source_name);
  const json doc = parseJsonText(r, json_text);
  if (!doc.is_object()) r.fail("(document)", "expected a JSON object");

  RobotModel m;
  const std::string format = r.string(r.field(doc, "", "format"), "format");
  if (format != kFormat) r.fail("format", "expected \"" + std::string(kFormat) + "\", got \"" + format + "\"");
  m.name = r.string(r.field(doc, "", "model"), "model");
  if (m.name.empty()) r.fail("model", "must not be empty");
  if (const json* desc = r.optionalField(doc, "description")) m.description = r.string(*desc, "description");

  const json& kin = r.field(doc, "", "kinematics");
  if (!kin.is_object()) r.fail("kinematics", "expected an object");
  const json& names = r.array(r.field(kin, "kinematics", "joint_names"), "kinematics.joint_names");
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string path = indexed("kinematics.joint_names", i);
    std::string n = r.string(names[i], path);
    if (std::find(m.joint_names.begin(), m.joint_names.end(), n) != m.joint_names.end()) {
      r.fail(path, "duplicate joint name '" + n + "'");
    }
    m.joint_names.push_back(std::move(n));
  }

  const bool has_dh = kin.contains("a") || kin.contains("d") || kin.contains("alpha");
  const bool has_gantry = kin.contains("beam_height") || kin.contains("ram_to_tcp");
  if (has_dh == has_gantry) {
    r.fail("kinematics", "needs either DH parameters (a, d, alpha, tcp_in_flange) or gantry parameters "
                         "(beam_height, ram_to_tcp)");
  }
  m.kinematics = has_dh ? KinematicsKind::kUrDh : KinematicsKind::kGantry;
  const int expected_dof = has_dh ? kUrJoints : kGantryJoints;
  if (m.dof() != expected_dof) {
    r.fail("kinematics.joint_names", "expected " + std::to_string(expected_dof) + " joints, got " +
                                         std::to_string(m.dof()));
  }
  if (has_dh) {
    parseUrKinematics(r, kin, m);
  } else {
    parseGantryKinematics(r, kin, m);
  }
  parseLimits(r, doc, m);
  parseCollision(r, doc, m);
  return m;
}

RobotModel loadRobotModel(const std::string& path) {
  std::ifstream in(path);
  DASH_THROW_UNLESS(in.good(), "cannot read robot model file '" + path + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parseRobotModel(buffer.str(), path);
}

std::shared_ptr<const RobotLibrary> RobotLibrary::loadDirectory(const std::string& folder) {
  namespace fs = std::filesystem;
  std::error_code ec;
  DASH_THROW_UNLESS(fs::is_directory(folder, ec), "robot model folder '" + folder + "' does not exist");
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file() && entry.path().extension() == ".json") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  auto lib = std::make_shared<RobotLibrary>();
  for (const auto& f : files) {
    auto model = std::make_shared<RobotModel>(loadRobotModel(f.string()));
    DASH_THROW_UNLESS(lib->find(model->name) == nullptr,
                      f.string() + ": model: duplicate model name '" + model->name + "'");
    lib->models_.push_back(std::move(model));
  }
  return lib;
}

std::shared_ptr<const RobotLibrary> RobotLibrary::loadDefault() {
  return loadDirectory(dataDirectory() + "/robots");
}

const RobotModel* RobotLibrary::find(const std::string& name) const {
  for (const auto& m : models_) {
    if (m->name == name) return m.get();
  }
  return nullptr;
}

const RobotModel& RobotLibrary::get(const std::string& name) const {
  const RobotModel* m = find(name);
  if (m == nullptr) {
    std::string known;
    for (const auto& n : names()) known += (known.empty() ? "" : ", ") + n;
    throw InputError("unknown robot model '" + name + "' (known: " + known + ")");
  }
  return *m;
}

std::vector<std::string> RobotLibrary::names() const {
  std::vector<std::string> out;
  for (const auto& m : models_) out.push_back(m->name);
  return out;
}

}  // namespace dash
