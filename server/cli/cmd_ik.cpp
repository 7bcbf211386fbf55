// dashbench ik: all inverse-kinematics solutions of one robot model for a TCP pose, as JSON.
#include <cstdio>
#include <nlohmann/json.hpp>

#include "engine/core/check.h"
#include "engine/robots/kinematics.h"
#include "server/cli/args.h"
#include "server/cli/command.h"

namespace dash::cli {

// Defined in cmd_fk.cpp.
Pose parsePoseArgument(const std::string& text, const std::string& what);

extern const char* const kIkHelp;
const char* const kIkHelp =
    "usage: dashbench ik --robot MODEL --tcp x,y,z,qx,qy,qz,qw [--base x,y,z,qx,qy,qz,qw]\n"
    "                    [--q6-reference RAD]\n"
    "Inverse kinematics of a robot model from data/robots for a TCP pose in the world frame. Prints a\n"
    "JSON list of solutions, each a list of joint values within the joint limits, wrapped into\n"
    "[-pi, pi] (ur5e: up to 8; gantry3: 0 or 1, the tool must point down). An unreachable pose prints [].\n"
    "--q6-reference: the wrist-3 angle used at a wrist singularity (ur5e; default 0).\n";

int runIk(const std::vector<std::string>& words) {
  Args args(words, {.options = {"robot", "tcp", "base", "q6-reference"}});
  if (!args.positional().empty()) throw InputError("unexpected argument '" + args.positional()[0] + "'");
  const auto library = RobotLibrary::loadDefault();
  const RobotModel& model = library->get(args.require("robot"));
  const Pose X_WT = parsePoseArgument(args.require("tcp"), "--tcp");
  const Pose X_WB = args.has("base") ? parsePoseArgument(args.require("base"), "--base") : Pose::Identity();
  std::vector<JointVector> solutions;
  if (model.kinematics == KinematicsKind::kUrDh) {
    std::array<JointVector, kUrMaxIkSolutions> buffer;
    const int n = inverseKinematicsUr(model, X_WB, X_WT, buffer, args.number("q6-reference", 0.0));
    solutions.assign(buffer.begin(), buffer.begin() + n);
  } else {
    DASH_THROW_UNLESS(!args.has("q6-reference"), "--q6-reference applies to UR arms only");
    solutions = inverseKinematics(model, X_WB, X_WT);
  }
  nlohmann::json out = nlohmann::json::array();
  for (const JointVector& q : solutions) out.push_back(std::vector<double>(q.data(), q.data() + q.size()));
  std::printf("%s\n", out.dump().c_str());
  return kExitOk;
}

}  // namespace dash::cli
