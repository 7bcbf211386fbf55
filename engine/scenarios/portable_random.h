#pragma once
// Random draws whose values are the same with every standard library. std::uniform_real_distribution,
// std::uniform_int_distribution and std::shuffle are implementation-defined; mt19937_64's raw output is
// not. Generators draw only through these.
#include <cstdint>
#include <utility>
#include <vector>

#include "engine/core/check.h"
#include "engine/core/rng.h"

namespace dash::portable {

/// Uniform in [0, 1): the top 53 bits of one engine output.
inline double uniform01(Rng& rng) { return static_cast<double>(rng.engine()() >> 11) * 0x1.0p-53; }

inline double uniform(Rng& rng, double lo, double hi) { return lo + (hi - lo) * uniform01(rng); }

/// Uniform integer in [lo, hi] (inclusive), by rejection (no modulo bias).
inline std::int64_t integer(Rng& rng, std::int64_t lo, std::int64_t hi) {
  DASH_DEMAND(lo <= hi);
  const std::uint64_t span = static_cast<std::uint64_t>(hi - lo) + 1;  // 0 means the full 2^64 range
  if (span == 0) return static_cast<std::int64_t>(rng.engine()());
  const std::uint64_t limit = UINT64_MAX - UINT64_MAX % span;
  std::uint64_t x = rng.engine()();
  while (x >= limit) x = rng.engine()();
  return lo + static_cast<std::int64_t>(x % span);
}

/// Fisher-Yates shuffle.
template <class T>
void shuffle(std::vector<T>& items, Rng& rng) {
  for (std::size_t i = items.size(); i > 1; --i) {
    const auto j = static_cast<std::size_t>(integer(rng, 0, static_cast<std::int64_t>(i) - 1));
    std::swap(items[i - 1], items[j]);
  }
}

}  // namespace dash::portable
