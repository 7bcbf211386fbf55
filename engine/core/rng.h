#pragma once
// One local random generator per run, seeded from the run's parameters (never global state).
#include <cstdint>
#include <random>

namespace dash {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : engine_(seed), seed_(seed) {}

  std::uint64_t seed() const { return seed_; }
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(engine_); }
  double uniform01() { return uniform(0.0, 1.0); }
  double gaussian(double mean, double stddev) { return std::normal_distribution<double>(mean, stddev)(engine_); }
  /// Uniform integer in [lo, hi] (inclusive).
  std::int64_t integer(std::int64_t lo, std::int64_t hi) {
    return std::uniform_int_distribution<std::int64_t>(lo, hi)(engine_);
  }
  std::mt19937_64& engine() { return engine_; }

  /// A seed for a child stream (e.g. a retry of a generator), derived deterministically.
  static std::uint64_t derive(std::uint64_t seed, std::uint64_t stream) {
    // splitmix64 of the pair: same inputs give the same seed on every machine.
    std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (stream + 1);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }

 private:
  std::mt19937_64 engine_;
  std::uint64_t seed_;
};

}  // namespace dash
