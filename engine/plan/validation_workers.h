#pragma once
// The validator's geometry checks spread over worker threads: how many, and running them.
#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace dash::validation {

/// Threads for `items` pieces of work: `requested` (0: the hardware's), no more than one per
/// `min_items_per_thread` (below that more threads cost more than they save), at least one.
inline std::size_t workerCount(int requested, std::size_t items, std::size_t min_items_per_thread) {
  const std::size_t wanted = requested > 0 ? static_cast<std::size_t>(requested)
                                           : std::max(1u, std::thread::hardware_concurrency());
  return std::max<std::size_t>(1, std::min(wanted, items / min_items_per_thread));
}

/// Calls work(w) for every w below `threads`, each on a thread of its own (on this one when there is
/// just one), and returns when all have finished.
template <class Work>
void runWorkers(std::size_t threads, const Work& work) {
  if (threads == 1) {
    work(std::size_t{0});
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (std::size_t w = 0; w < threads; ++w) pool.emplace_back(work, w);
  for (std::thread& thread : pool) thread.join();
}

}  // namespace dash::validation
