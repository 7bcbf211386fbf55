#include "engine/scene/scene_json.h"

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "engine/core/check.h"
#include "engine/core/json_parse.h"
#include "engine/core/json_reader.h"
#include "engine/geometry/pose_json.h"

namespace dash {

namespace {

// ordered_json keeps the file's key order: generator params stay in order, output follows the contract.
using Json = nlohmann::ordered_json;

/// The shared field reader plus what scenes add: poses and box shapes.
class Validator : public JsonReader<Json> {
 public:
  explicit Validator(const std::string& source) : JsonReader<Json>(source, "scene") {}

  Pose pose(const Json& value, const std::string& path) const {
    requireObject(value, path);
    return readPose(*this, value, path);
  }

  BoxShape box(const Json& value, const std::string& path) const {
    requireObject(value, path);
    const std::string type = string(field(value, path, "type"), join(path, "type"));
    if (type != "box") fail(join(path, "type"), "unknown shape type \"" + type + "\" (only \"box\")");
    const std::string size_path = join(path, "size");
    const auto size = numbers(field(value, path, "size"), size_path, 3);
    for (std::size_t i = 0; i < 3; ++i) {
      if (size[i] <= 0.0) fail(index(size_path, i), "box size must be positive");
    }
    return BoxShape{.size = Vec3(size[0], size[1], size[2])};
  }
};

SceneGenerator parseGenerator(const Validator& v, const Json& j, const std::string& path) {
  v.requireObject(j, path);
  SceneGenerator g;
  g.name = v.nonEmptyString(v.field(j, path, "name"), Validator::join(path, "name"));
  const std::string params_path = Validator::join(path, "params");
  const Json& params = v.field(j, path, "params");
  v.requireObject(params, params_path);
  for (const auto& [key, value] : params.items()) {
    const std::string p = Validator::join(params_path, key);
    if (value.is_string()) {
      g.params.emplace_back(key, value.get<std::string>());
    } else if (value.is_number()) {
      g.params.emplace_back(key, v.number(value, p));
    } else {
      v.fail(p, "expected a number or a string");
    }
  }
  const std::string seed_path = Validator::join(path, "seed");
  const Json& seed = v.field(j, path, "seed");
  if (seed.is_number_unsigned()) {
    g.seed = seed.get<std::uint64_t>();
  } else if (seed.is_number_integer()) {
    v.fail(seed_path, "seed must not be negative");
  } else {
    v.fail(seed_path, "expected a non-negative integer");
  }
  return g;
}

SceneRobot parseRobot(const Validator& v, const Json& j, const std::string& path, const RobotLibrary& library) {
  v.requireObject(j, path);
  SceneRobot r;
  r.id = v.nonEmptyString(v.field(j, path, "id"), Validator::join(path, "id"));
  r.model_name = v.string(v.field(j, path, "model"), Validator::join(path, "model"));
  r.model = library.find(r.model_name);
  if (r.model == nullptr) v.fail(Validator::join(path, "model"), "unknown robot model \"" + r.model_name + "\"");
  r.X_WB = v.pose(v.field(j, path, "base"), Validator::join(path, "base"));
  const std::string home_path = Validator::join(path, "home");
  const auto home = v.numbersAt(j, path, "home", static_cast<std::size_t>(r.model->dof()));
  r.home = JointVector::Map(home.data(), static_cast<Eigen::Index>(home.size()));
  for (int i = 0; i < r.model->dof(); ++i) {
    const double lo = r.model->limits.position_min[i];
    const double hi = r.model->limits.position_max[i];
    if (r.home[i] < lo || r.home[i] > hi) {
      std::ostringstream msg;
      msg << "joint " << r.model->joint_names[static_cast<std::size_t>(i)] << " = " << r.home[i]
          << " is outside its limits [" << lo << ", " << hi << "]";
      v.fail(Validator::index(home_path, static_cast<std::size_t>(i)), msg.str());
    }
  }
  const std::string caps_path = Validator::join(path, "capabilities");
  const Json& caps = v.array(v.field(j, path, "capabilities"), caps_path);
  for (std::size_t i = 0; i < caps.size(); ++i) {
    r.capabilities.push_back(v.nonEmptyString(caps[i], Validator::index(caps_path, i)));
  }
  return r;
}

SceneObstacle parseObstacle(const Validator& v, const Json& j, const std::string& path) {
  v.requireObject(j, path);
  SceneObstacle o;
  o.id = v.nonEmptyString(v.field(j, path, "id"), Validator::join(path, "id"));
  o.shape = v.box(v.field(j, path, "shape"), Validator::join(path, "shape"));
  o.X_WO = v.pose(v.field(j, path, "pose"), Validator::join(path, "pose"));
  return o;
}

SceneSurface parseSurface(const Validator& v, const Json& j, const std::string& path) {
  v.requireObject(j, path);
  SceneSurface s;
  s.id = v.nonEmptyString(v.field(j, path, "id"), Validator::join(path, "id"));
  s.z = v.number(v.field(j, path, "z"), Validator::join(path, "z"));
  const std::string poly_path = Validator::join(path, "polygon");
  const Json& poly = v.array(v.field(j, path, "polygon"), poly_path);
  if (poly.size() < 3) v.fail(poly_path, "a polygon needs at least 3 points, got " + std::to_string(poly.size()));
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto xy = v.numbers(poly[i], Validator::index(poly_path, i), 2);
    s.polygon.emplace_back(xy[0], xy[1]);
  }
  double twice_area = 0.0;
  for (std::size_t i = 0; i < s.polygon.size(); ++i) {
    const auto& a = s.polygon[i];
    const auto& b = s.polygon[(i + 1) % s.polygon.size()];
    twice_area += a.x() * b.y() - b.x() * a.y();
  }
  if (std::abs(twice_area) < 1e-12) v.fail(poly_path, "polygon has zero area");
  return s;
}

SceneObject parseObject(const Validator& v, const Json& j, const std::string& path) {
  v.requireObject(j, path);
  SceneObject o;
  o.id = v.nonEmptyString(v.field(j, path, "id"), Validator::join(path, "id"));
  o.shape = v.box(v.field(j, path, "shape"), Validator::join(path, "shape"));
  o.X_WO_start = v.pose(v.field(j, path, "start"), Validator::join(path, "start"));
  if (const auto it = j.find("goal"); it != j.end() && !it->is_null()) {
    o.X_WO_goal = v.pose(*it, Validator::join(path, "goal"));
  }
  if (const auto it = j.find("fixed"); it != j.end()) o.fixed = v.boolean(*it, Validator::join(path, "fixed"));
  return o;
}

SceneTask parseTask(const Validator& v, const Json& j, const std::string& path, const Scene& scene) {
  v.requireObject(j, path);
  SceneTask t;
  const std::string type_path = Validator::join(path, "type");
  const std::string type = v.string(v.field(j, path, "type"), type_path);
  if (type != "inspect") v.fail(type_path, "unknown task type \"" + type + "\" (only \"inspect\")");
  t.type = SceneTask::Type::kInspect;
  const std::string target_path = Validator::join(path, "target");
  t.target = v.string(v.field(j, path, "target"), target_path);
  t.target_object = scene.objectIndex(t.target);
  if (t.target_object < 0) v.fail(target_path, "unknown object \"" + t.target + "\"");
  t.X_WT = v.pose(v.field(j, path, "pose"), Validator::join(path, "pose"));
  if (const auto it = j.find("requires_removed"); it != j.end() && !it->is_null()) {
    const std::string rr_path = Validator::join(path, "requires_removed");
    t.requires_removed = v.string(*it, rr_path);
    t.requires_removed_object = scene.objectIndex(*t.requires_removed);
    if (t.requires_removed_object < 0) v.fail(rr_path, "unknown object \"" + *t.requires_removed + "\"");
  }
  t.capability = v.nonEmptyString(v.field(j, path, "capability"), Validator::join(path, "capability"));
  return t;
}

/// Robots, obstacles and objects share one id space (a plan's events name them); surfaces have their own.
void checkUniqueIds(const Validator& v, const Scene& scene) {
  std::map<std::string, std::string> seen;  // id -> path of its first use
  auto visit = [&](const std::string& id, const std::string& path) {
    const auto [it, inserted] = seen.emplace(id, path);
    if (!inserted) v.fail(path + ".id", "duplicate id \"" + id + "\" (also " + it->second + ")");
  };
  for (std::size_t i = 0; i < scene.robots.size(); ++i) visit(scene.robots[i].id, Validator::index("robots", i));
  for (std::size_t i = 0; i < scene.obstacles.size(); ++i) {
    visit(scene.obstacles[i].id, Validator::index("obstacles", i));
  }
  for (std::size_t i = 0; i < scene.objects.size(); ++i) visit(scene.objects[i].id, Validator::index("objects", i));
  std::map<std::string, std::string> surfaces;
  for (std::size_t i = 0; i < scene.surfaces.size(); ++i) {
    const std::string path = Validator::index("surfaces", i);
    const auto [it, inserted] = surfaces.emplace(scene.surfaces[i].id, path);
    if (!inserted) v.fail(path + ".id", "duplicate surface id \"" + it->first + "\" (also " + it->second + ")");
  }
}

template <class Item, class ParseOne>
std::vector<Item> parseList(const Validator& v, const Json& root, const std::string& key, ParseOne parse_one) {
  const Json& list = v.array(v.field(root, "", key), key);
  std::vector<Item> out;
  out.reserve(list.size());
  for (std::size_t i = 0; i < list.size(); ++i) out.push_back(parse_one(list[i], Validator::index(key, i)));
  return out;
}

// ---- writing ----

Json numberJson(double x) {
  // Integral values (counts in generator params) are written as integers so they read back the same.
  if (std::nearbyint(x) == x && std::abs(x) < 1e15) return static_cast<std::int64_t>(x);
  return x;
}

Json poseJson(const Pose& X) {
  const Vec3 p = X.translation();
  const auto q = quatXYZW(X);
  return Json{{"p", {p.x(), p.y(), p.z()}}, {"q", {q[0], q[1], q[2], q[3]}}};
}

Json boxJson(const BoxShape& box) {
  return Json{{"type", "box"}, {"size", {box.size.x(), box.size.y(), box.size.z()}}};
}

}  // namespace

Scene parseScene(const std::string& json_text, std::shared_ptr<const RobotLibrary> library,
                 const std::string& source_name) {
  DASH_DEMAND(library != nullptr);
  const Validator v(source_name);
  const Json root = parseJsonText(v, json_text);
  v.requireObject(root, "");
  const std::string format = v.string(v.field(root, "", "format"), "format");
  if (format != kSceneFormat) {
    v.fail("format", "unknown format \"" + format + "\" (expected \"" + kSceneFormat + "\")");
  }

  Scene scene;
  scene.library = library;
  scene.name = v.nonEmptyString(v.field(root, "", "name"), "name");
  if (const auto it = root.find("generator"); it != root.end() && !it->is_null()) {
    scene.generator = parseGenerator(v, *it, "generator");
  }
  scene.robots = parseList<SceneRobot>(v, root, "robots", [&](const Json& j, const std::string& path) {
    return parseRobot(v, j, path, *library);
  });
  scene.obstacles = parseList<SceneObstacle>(v, root, "obstacles", [&](const Json& j, const std::string& path) {
    return parseObstacle(v, j, path);
  });
  scene.surfaces = parseList<SceneSurface>(v, root, "surfaces", [&](const Json& j, const std::string& path) {
    return parseSurface(v, j, path);
  });
  scene.objects = parseList<SceneObject>(v, root, "objects", [&](const Json& j, const std::string& path) {
    return parseObject(v, j, path);
  });
  checkUniqueIds(v, scene);
  // Tasks may be omitted (no extra goals); they reference objects, so they come last.
  if (const auto it = root.find("tasks"); it != root.end()) {
    const Json& tasks = v.array(*it, "tasks");
    for (std::size_t i = 0; i < tasks.size(); ++i) {
      scene.tasks.push_back(parseTask(v, tasks[i], Validator::index("tasks", i), scene));
    }
  }
  if (const auto it = root.find("end_at_home"); it != root.end()) {
    scene.end_at_home = v.boolean(*it, "end_at_home");
  }
  return scene;
}

Scene loadScene(const std::string& path, std::shared_ptr<const RobotLibrary> library) {
  std::ifstream in(path, std::ios::binary);
  DASH_THROW_UNLESS(in.good(), path + ": cannot open the scene file");
  std::ostringstream text;
  text << in.rdbuf();
  return parseScene(text.str(), std::move(library), path);
}

std::string sceneToJson(const Scene& scene) {
  Json root;
  root["format"] = kSceneFormat;
  root["name"] = scene.name;
  if (scene.generator) {
    Json params = Json::object();
    for (const auto& [key, value] : scene.generator->params) {
      if (const auto* x = std::get_if<double>(&value)) {
        params[key] = numberJson(*x);
      } else {
        params[key] = std::get<std::string>(value);
      }
    }
    root["generator"] = Json{{"name", scene.generator->name}, {"params", params}, {"seed", scene.generator->seed}};
  }
  Json robots = Json::array();
  for (const auto& r : scene.robots) {
    Json home = Json::array();
    for (Eigen::Index i = 0; i < r.home.size(); ++i) home.push_back(r.home[i]);
    robots.push_back(Json{{"id", r.id}, {"model", r.model_name}, {"base", poseJson(r.X_WB)}, {"home", home},
                          {"capabilities", r.capabilities}});
  }
  root["robots"] = robots;
  Json obstacles = Json::array();
  for (const auto& o : scene.obstacles) {
    obstacles.push_back(Json{{"id", o.id}, {"shape", boxJson(o.shape)}, {"pose", poseJson(o.X_WO)}});
  }
  root["obstacles"] = obstacles;
  Json surfaces = Json::array();
  for (const auto& s : scene.surfaces) {
    Json polygon = Json::array();
    for (const auto& xy : s.polygon) polygon.push_back({xy.x(), xy.y()});
    surfaces.push_back(Json{{"id", s.id}, {"z", s.z}, {"polygon", polygon}});
  }
  root["surfaces"] = surfaces;
  Json objects = Json::array();
  for (const auto& o : scene.objects) {
    Json j{{"id", o.id}, {"shape", boxJson(o.shape)}, {"start", poseJson(o.X_WO_start)}};
    if (o.X_WO_goal) j["goal"] = poseJson(*o.X_WO_goal);
    j["fixed"] = o.fixed;
    objects.push_back(j);
  }
  root["objects"] = objects;
  Json tasks = Json::array();
  for (const auto& t : scene.tasks) {
    Json j{{"type", "inspect"}, {"target", t.target}, {"pose", poseJson(t.X_WT)}};
    if (t.requires_removed) j["requires_removed"] = *t.requires_removed;
    j["capability"] = t.capability;
    tasks.push_back(j);
  }
  root["tasks"] = tasks;
  root["end_at_home"] = scene.end_at_home;
  return root.dump(1) + "\n";
}

void saveScene(const Scene& scene, const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  DASH_THROW_UNLESS(out.good(), path + ": cannot write the scene file");
  out << sceneToJson(scene);
  out.flush();
  DASH_THROW_UNLESS(out.good(), path + ": writing the scene file failed");
}

}  // namespace dash
