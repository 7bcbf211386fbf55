#include "server/dispatch/tolerances.h"

#include <cmath>
#include <cstdio>
#include <limits>

#include "engine/core/check.h"

namespace dash::dispatch {

double ToleranceSpec::forJoint(const std::string& name) const {
  const auto it = joints.find(name);
  return it != joints.end() ? it->second : all;
}

JointVector ToleranceSpec::resolve(const std::vector<std::string>& joint_names) const {
  JointVector out(static_cast<Eigen::Index>(joint_names.size()));
  for (std::size_t i = 0; i < joint_names.size(); ++i) out[static_cast<Eigen::Index>(i)] = forJoint(joint_names[i]);
  return out;
}

void ToleranceSpec::validate(const std::string& what) const {
  DASH_THROW_UNLESS(std::isfinite(all) && all >= 0.0, what + ": must be a non-negative number");
  for (const auto& [name, value] : joints) {
    DASH_THROW_UNLESS(std::isfinite(value) && value >= 0.0, what + "." + name + ": must be a non-negative number");
  }
}

void ToleranceSpec::validateJointNames(const std::set<std::string>& known, const std::string& what) const {
  for (const auto& [name, value] : joints) {
    if (known.count(name) != 0) continue;
    std::string list;
    for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
    throw InputError(what + "." + name + ": not a joint of the plan's arms (" + list + "; \"all\" for the rest)");
  }
}

ToleranceCheck checkTolerance(const JointVector& actual, const JointVector& reference, const JointVector& tolerance) {
  ToleranceCheck out;
  if (actual.size() != reference.size()) {
    out.violated = true;
    return out;
  }
  double worst_excess = -1.0;
  for (Eigen::Index j = 0; j < actual.size(); ++j) {
    double error = std::abs(actual[j] - reference[j]);
    if (std::isnan(error)) error = std::numeric_limits<double>::infinity();
    const double tol = j < tolerance.size() ? tolerance[j] : 0.0;
    const bool over = tol > 0.0 && error > tol;
    if (over && error - tol > worst_excess) {
      worst_excess = error - tol;
      out = {true, static_cast<int>(j), error, tol};
    } else if (!out.violated && error > out.error) {
      out = {false, static_cast<int>(j), error, tol};
    } else if (out.joint < 0) {
      out = {false, static_cast<int>(j), error, tol};
    }
  }
  return out;
}

std::string describeViolation(const ToleranceCheck& check, const std::vector<std::string>& joint_names,
                              const std::string& kind, double t) {
  if (check.joint < 0) return "the joint state has the wrong size";
  const auto j = static_cast<std::size_t>(check.joint);
  const std::string name = j < joint_names.size() ? " (" + joint_names[j] + ")" : "";
  char text[200];
  std::snprintf(text, sizeof text, "joint %d%s %.4f rad off at t=%.3f s (%s tolerance %.4f)", check.joint, name.c_str(),
                check.error, t, kind.c_str(), check.tolerance);
  return text;
}

}  // namespace dash::dispatch
