// dashbench fk: forward kinematics of one robot model, as JSON.
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "engine/geometry/pose_json.h"
#include "engine/robots/kinematics.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

// Shared with cmd_ik.cpp.
Pose parsePoseArgument(const std::string& text, const std::string& what);
nlohmann::json poseJson(const Pose& X);

/// "x,y,z,qx,qy,qz,qw" (quaternion of unit length, as in the file contract).
Pose parsePoseArgument(const std::string& text, const std::string& what) {
  const std::vector<double> v = parseNumberList(text, what);
  DASH_THROW_UNLESS(v.size() == 7, what + ": expected 7 numbers x,y,z,qx,qy,qz,qw, got " + std::to_string(v.size()));
  const double norm = std::sqrt(v[3] * v[3] + v[4] * v[4] + v[5] * v[5] + v[6] * v[6]);
  DASH_THROW_UNLESS(std::abs(norm - 1.0) <= kUnitQuaternionTolerance,
                    what + ": quaternion is not unit length (|q| = " + std::to_string(norm) + ")");
  return makePose(Vec3(v[0], v[1], v[2]), quatFromXYZW({v[3], v[4], v[5], v[6]}));
}

/// {"p": [x, y, z], "q": [qx, qy, qz, qw]} with qw >= 0.
nlohmann::json poseJson(const Pose& X) {
  auto q = quatXYZW(X);
  if (q[3] < 0.0) {
    for (double& c : q) c = -c;
  }
  const Vec3 p = X.translation();
  return {{"p", {p.x(), p.y(), p.z()}}, {"q", {q[0], q[1], q[2], q[3]}}};
}

extern const char* const kFkHelp;
const char* const kFkHelp =
    "usage: dashbench fk --robot MODEL --q Q1,Q2,... [--base x,y,z,qx,qy,qz,qw]\n"
    "Forward kinematics of a robot model from data/robots (ur5e, gantry3). Prints\n"
    "{\"flange\": POSE, \"tcp\": POSE} with POSE = {\"p\": [x, y, z], \"q\": [qx, qy, qz, qw]} in the world\n"
    "frame; --base is the robot's mounting pose (default: identity). For the gantry the flange is the TCP.\n";

int runFk(const std::vector<std::string>& words) {
  Args args(words, {.options = {"robot", "q", "base"}});
  if (!args.positional().empty()) throw InputError("unexpected argument '" + args.positional()[0] + "'");
  const auto library = RobotLibrary::loadDefault();
  const RobotModel& model = library->get(args.require("robot"));
  const std::vector<double> values = parseNumberList(args.require("q"), "--q");
  DASH_THROW_UNLESS(static_cast<int>(values.size()) == model.dof(),
                    "--q: expected " + std::to_string(model.dof()) + " joint values for " + model.name + ", got " +
                        std::to_string(values.size()));
  JointVector q(model.dof());
  for (int i = 0; i < model.dof(); ++i) q[i] = values[static_cast<std::size_t>(i)];
  const Pose X_WB = args.has("base") ? parsePoseArgument(args.require("base"), "--base") : Pose::Identity();
  const FkResult fk = forwardKinematics(model, X_WB, q);
  const nlohmann::json out = {{"flange", poseJson(fk.X_WF)}, {"tcp", poseJson(fk.X_WT)}};
  std::printf("%s\n", out.dump().c_str());
  return kExitOk;
}

}  // namespace dash::cli
