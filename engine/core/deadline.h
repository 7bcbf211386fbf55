#pragma once
// A time limit plus an external stop flag (Ctrl-C, a cancelled batch): planners poll expired().
#include <atomic>
#include <chrono>
#include <limits>

#include "engine/core/stopwatch.h"

namespace dash {

class Deadline {
 public:
  /// No limit.
  Deadline() : end_(Clock::time_point::max()) {}
  explicit Deadline(double seconds_from_now, const std::atomic<bool>* stop_flag = nullptr)
      : end_(seconds_from_now >= 1e9 ? Clock::time_point::max()
                                     : Clock::now() + std::chrono::duration_cast<Clock::duration>(
                                                          std::chrono::duration<double>(seconds_from_now))),
        stop_flag_(stop_flag) {}

  bool expired() const {
    if (stop_flag_ != nullptr && stop_flag_->load(std::memory_order_relaxed)) return true;
    return Clock::now() >= end_;
  }
  bool stopRequested() const { return stop_flag_ != nullptr && stop_flag_->load(std::memory_order_relaxed); }
  double secondsLeft() const {
    if (end_ == Clock::time_point::max()) return std::numeric_limits<double>::infinity();
    return std::chrono::duration<double>(end_ - Clock::now()).count();
  }

 private:
  Clock::time_point end_;
  const std::atomic<bool>* stop_flag_ = nullptr;
};

}  // namespace dash
