#pragma once
// OMPL objects whose randomness comes from the planner run's seed, not from OMPL's process-wide seed
// sequence. OMPL seeds every RNG it creates from one global generator that can be seeded only once per
// process (ompl::RNG::setSeed), so a run's samples used to depend on every OMPL object created before
// it in the same process. Here a run opens an OmplSeedScope with its seed, and each sampler, planner
// and path simplifier it creates gets a local seed from that scope, in creation order: the same seed
// gives the same samples, in a fresh process or after other runs.
//
// This header includes no OMPL header (a run opens a scope without parsing OMPL's planners); the
// seeded planner classes are in seeded_ompl_planners.h, for the three files that create them.
#include <cstdint>

namespace ompl::base {
class StateSpace;
}

namespace dash {

/// The OMPL seeds of the planner run on this thread while it lives (scopes nest; the innermost wins).
class OmplSeedScope {
 public:
  explicit OmplSeedScope(std::uint64_t run_seed);
  ~OmplSeedScope();
  OmplSeedScope(const OmplSeedScope&) = delete;
  OmplSeedScope& operator=(const OmplSeedScope&) = delete;

  /// A non-zero 32-bit seed (OMPL ignores 0), different for each call (splitmix64 over the run seed).
  std::uint_fast32_t next();

 private:
  std::uint64_t state_;
  OmplSeedScope* outer_;
};

/// The next seed of the innermost scope on this thread; without a scope, of a fixed default sequence.
std::uint_fast32_t nextOmplSeed();

/// Every sampler `space` allocates from now on is seeded with nextOmplSeed() (real-vector spaces).
void seedStateSamplers(ompl::base::StateSpace& space);

}  // namespace dash
