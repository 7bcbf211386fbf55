#pragma once
// A hash of a sequence of doubles by their bits (FNV-1a), for the memo tables keyed by configurations
// and times: the schedule checker's standing-still verdicts (engine/conflict/schedule_checker.h) and the
// task conflict detector's handover verdicts (engine/task/task_conflict_detection.cpp). Equal keys are
// compared in full by the tables; the hash only spreads them.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace dash {

struct DoublesHash {
  std::size_t operator()(const std::vector<double>& values) const {
    std::size_t h = 1469598103934665603ull;
    for (const double x : values) {
      std::uint64_t bits;
      std::memcpy(&bits, &x, sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
    }
    return h;
  }
};

}  // namespace dash
