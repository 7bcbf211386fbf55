#pragma once
// A small fixed pool of threads for conflict resolution's independent checks (issue 38 item 3): lane 0
// is the calling thread, lanes 1..n-1 are threads started once and kept, woken for each run. The
// checker's calls are many and short, so threads are not started per call; what each lane computes
// is reduced by the caller in a fixed order, so the results do not depend on the number of lanes.
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace dash {

/// Lanes for `requested` threads: requested when above 0 (at most kMaxCheckLanes), else the hardware's
/// capped at 2 (a run uses its two cores; more would oversubscribe the machines the benchmarks run
/// on). At least 1.
inline constexpr std::size_t kMaxCheckLanes = 8;
std::size_t checkLanes(int requested);

class CheckPool {
 public:
  explicit CheckPool(std::size_t lanes);
  ~CheckPool();
  CheckPool(const CheckPool&) = delete;
  CheckPool& operator=(const CheckPool&) = delete;

  std::size_t lanes() const { return workers_.size() + 1; }
  /// Calls work(lane) once for every lane and returns when all have finished: lane 0 on this thread,
  /// each other lane on its worker, or on this thread when the worker has not taken it by then. An
  /// exception of any lane is rethrown here (the first, by lane order).
  void run(const std::function<void(std::size_t)>& work);

 private:
  void serve(std::size_t lane);
  /// Takes `lane`'s share of run `generation` (under mutex_); false when it was already taken.
  bool claim(std::size_t lane, std::uint64_t generation);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  const std::function<void(std::size_t)>* work_ = nullptr;
  std::uint64_t generation_ = 0;
  std::vector<std::uint64_t> claimed_;   ///< per lane: the last run whose share was taken
  std::vector<std::uint64_t> finished_;  ///< per lane: the last run whose share finished
  bool stop_ = false;
  std::vector<std::exception_ptr> errors_;
};

}  // namespace dash
