#pragma once
#include <chrono>

namespace dash {

using Clock = std::chrono::steady_clock;

/// Elapsed time since construction or the last restart(), in seconds.
class Stopwatch {
 public:
  Stopwatch() : start_(Clock::now()) {}
  void restart() { start_ = Clock::now(); }
  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  Clock::time_point start_;
};

}  // namespace dash
