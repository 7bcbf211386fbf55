#pragma once
// OMPL's planners and path simplifier with their RNG seeded from the planner run's seed
// (seeded_ompl.h's OmplSeedScope). Apart from seeded_ompl.h because OMPL's planner headers are heavy
// (PRM.h alone preprocesses to about 240,000 lines): only the files that create these include it.
#include <ompl/geometric/PathSimplifier.h>
#include <ompl/geometric/planners/prm/PRM.h>
#include <ompl/geometric/planners/rrt/RRTConnect.h>

#include <utility>

#include "engine/motion/seeded_ompl.h"

namespace dash {

/// An OMPL class with its own RNG (the protected rng_) seeded with nextOmplSeed().
template <class OmplClass>
class Seeded : public OmplClass {
 public:
  template <class... Args>
  explicit Seeded(Args&&... args) : OmplClass(std::forward<Args>(args)...) {
    this->rng_.setLocalSeed(nextOmplSeed());
  }
};

using SeededRRTConnect = Seeded<ompl::geometric::RRTConnect>;
using SeededPRM = Seeded<ompl::geometric::PRM>;
using SeededPathSimplifier = Seeded<ompl::geometric::PathSimplifier>;

}  // namespace dash
