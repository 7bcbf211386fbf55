#include "engine/motion/seeded_ompl.h"

#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/util/Console.h>

#include <memory>

namespace dash {
namespace {

thread_local OmplSeedScope* innermost = nullptr;

class SeededRealVectorSampler : public ompl::base::RealVectorStateSampler {
 public:
  explicit SeededRealVectorSampler(const ompl::base::StateSpace* space) : RealVectorStateSampler(space) {
    rng_.setLocalSeed(nextOmplSeed());
  }
};

}  // namespace

OmplSeedScope::OmplSeedScope(std::uint64_t run_seed)
    : state_(run_seed * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull), outer_(innermost) {
  ompl::msg::setLogLevel(ompl::msg::LOG_NONE);  // outcomes are reported through our own events
  innermost = this;
}

OmplSeedScope::~OmplSeedScope() { innermost = outer_; }

std::uint_fast32_t OmplSeedScope::next() {
  std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<std::uint_fast32_t>(z & 0x7fffffffu) | 1u;
}

std::uint_fast32_t nextOmplSeed() {
  if (innermost != nullptr) return innermost->next();
  thread_local OmplSeedScope fallback(0);  // registers itself as innermost; a run's scope nests inside
  return fallback.next();
}

void seedStateSamplers(ompl::base::StateSpace& space) {
  space.setStateSamplerAllocator([](const ompl::base::StateSpace* s) -> ompl::base::StateSamplerPtr {
    return std::make_shared<SeededRealVectorSampler>(s);
  });
}

}  // namespace dash
