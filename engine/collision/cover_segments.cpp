// The covers along straight segments, kBatchLanes steps at a time (cover_check.h). Each step's
// configuration is computed exactly as the exact check computes it (q0 + t (q1 - q0), t = k / n).
#include <algorithm>

#include "engine/collision/cover_check.h"
#include "engine/core/check.h"

namespace dash::detail {

namespace {

using cover::L;

/// Lane l holds step k0 + l, or the last step of the block for the lanes past it.
void fillSteps(const JointVector& q0, const JointVector& q1, int n, int k0, int lanes, JointBatch& qb) {
  for (int l = 0; l < L; ++l) {
    const double t = static_cast<double>(k0 + std::min(l, lanes - 1)) / n;
    qb.set(l, q0 + t * (q1 - q0));
  }
}

void markCleared(const double* clear, int k0, int lanes, std::vector<std::uint8_t>& cleared) {
  const std::uint32_t bits = clearedLanes(clear, lanes);
  for (int l = 0; l < lanes; ++l) cleared[static_cast<std::size_t>(k0 + l)] = (bits >> l) & 1u;
}

/// Per-thread storage (a RobotCoverBatch is a few kB; a query may need one per robot).
struct CoverScratch {
  JointBatch q;
  FrameBatch frames;
  std::vector<RobotCoverBatch> movers;
  std::vector<RobotCoverBatch> parked;
};

CoverScratch& coverScratch() {
  thread_local CoverScratch scratch;
  return scratch;
}

}  // namespace

void coverSegmentSteps(const CollisionWorld& world, const CollisionContext& context, const RobotState& start,
                       const JointVector& q_end, int n, const CandidateView& view, std::vector<std::uint8_t>& cleared) {
  cleared.assign(static_cast<std::size_t>(std::max(n, 0)) + 1, 0);
  if (n < 2) return;
  const RobotGeometry& rg = world.robot(start.robot);
  CoverScratch& cs = coverScratch();
  cs.parked.resize(view.robots.size());
  for (std::size_t i = 0; i < view.robots.size(); ++i) coverFromPosed(world, context, view.robots[i], cs.parked[i]);
  cs.movers.resize(1);
  for (int k0 = 1; k0 < n; k0 += L) {
    const int lanes = std::min(L, n - k0);
    fillSteps(start.q, q_end, n, k0, lanes, cs.q);
    batchFrames(*rg.model, rg.robot->X_WB, cs.q, cs.frames);
    coverFromFrames(world, start.robot, cs.frames, start.held, cs.movers[0]);
    alignas(64) double clear[L];
    std::fill_n(clear, L, 1.0);
    clearAgainstCandidates(world, context, cs.movers[0], view, cs.parked, clear);
    markCleared(clear, k0, lanes, cleared);
  }
}

void coverMotionSteps(const CollisionWorld& world, CollisionContext& context, std::span<const RobotState> starts,
                      std::span<const JointVector> ends, CheckScope scope, std::span<const int> parked, int n,
                      std::vector<std::uint8_t>& cleared) {
  DASH_DEMAND(starts.size() == ends.size());
  cleared.assign(static_cast<std::size_t>(std::max(n, 0)) + 1, 0);
  if (n < 2) return;
  CoverScratch& cs = coverScratch();
  const bool robots = scope != CheckScope::kObjectsOnly;
  cs.parked.resize(robots ? parked.size() : 0);
  for (std::size_t i = 0; i < cs.parked.size(); ++i) coverFromPosed(world, context, parked[i], cs.parked[i]);
  cs.movers.resize(starts.size());
  for (int k0 = 1; k0 < n; k0 += L) {
    const int lanes = std::min(L, n - k0);
    alignas(64) double clear[L];
    std::fill_n(clear, L, 1.0);
    for (std::size_t i = 0; i < starts.size(); ++i) {
      const RobotGeometry& rg = world.robot(starts[i].robot);
      fillSteps(starts[i].q, ends[i], n, k0, lanes, cs.q);
      batchFrames(*rg.model, rg.robot->X_WB, cs.q, cs.frames);
      coverFromFrames(world, starts[i].robot, cs.frames, starts[i].held, cs.movers[i]);
      if (scope == CheckScope::kRobotsOnly) continue;
      clearAgainstCandidates(world, context, cs.movers[i], fullCandidates(world, context, starts[i].robot, scope), {},
                             clear);
    }
    if (robots) {
      for (std::size_t i = 0; i < cs.movers.size(); ++i) {
        for (std::size_t k = i + 1; k < cs.movers.size(); ++k) clearRobotPair(cs.movers[i], cs.movers[k], clear);
        for (const RobotCoverBatch& p : cs.parked) clearRobotPair(cs.movers[i], p, clear);
      }
    }
    markCleared(clear, k0, lanes, cleared);
  }
}

}  // namespace dash::detail
