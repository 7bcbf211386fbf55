#include "engine/motion/motion_context.h"

namespace dash {

namespace {
bool samePose(const Pose& a, const Pose& b) { return a.matrix() == b.matrix(); }
}  // namespace

bool MotionContext::sameAs(const MotionContext& o) const {
  if (held.object != o.held.object || (held.holding() && !samePose(held.X_TO, o.held.X_TO))) return false;
  if (layout.present != o.layout.present) return false;
  for (int j = 0; j < layout.size(); ++j)
    if (layout.isPresent(j) && !samePose(layout.X_WO[j], o.layout.X_WO[j])) return false;
  if (parked.size() != o.parked.size()) return false;
  for (std::size_t i = 0; i < parked.size(); ++i)
    if (parked[i].robot != o.parked[i].robot || parked[i].q != o.parked[i].q ||
        parked[i].held.object != o.parked[i].held.object)
      return false;
  if (avoid.size() != o.avoid.size()) return false;
  for (std::size_t i = 0; i < avoid.size(); ++i)
    if (avoid[i].min() != o.avoid[i].min() || avoid[i].max() != o.avoid[i].max()) return false;
  return true;
}

}  // namespace dash
