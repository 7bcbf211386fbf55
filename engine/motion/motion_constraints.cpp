#include "engine/motion/motion_constraints.h"

#include <cstdio>

namespace dash {

std::string MotionConstraint::describe(const Scene& scene) const {
  std::string out;
  for (const History& h : histories) {
    if (!out.empty()) out += ", ";
    out += scene.robots[h.robot].id + (h.step >= 0 ? " at step " + std::to_string(h.step) : " on its way home");
  }
  out += "; region: ";
  if (hasTimeRegion()) {
    char buffer[96];
    std::snprintf(buffer, sizeof buffer, "t in [%.3f, %.3f] s", t_begin, t_end);
    out += buffer;
  } else {
    for (std::size_t i = 0; i < configurations.size(); ++i) {
      const auto& [robot, q] = configurations[i];
      out += (i > 0 ? ", " : "") + scene.robots[robot].id + " q=(";
      for (int j = 0; j < q.size(); ++j) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%s%.3f", j > 0 ? " " : "", q[j]);
        out += buffer;
      }
      out += ")";
    }
  }
  return out;
}

}  // namespace dash
