#include "engine/conflict/check_pool.h"

#include <algorithm>

namespace dash {

std::size_t checkLanes(int requested) {
  if (requested > 0) return std::min(static_cast<std::size_t>(requested), kMaxCheckLanes);
  return std::clamp<std::size_t>(std::thread::hardware_concurrency(), 1, 2);
}

CheckPool::CheckPool(std::size_t lanes)
    : claimed_(std::max<std::size_t>(lanes, 1), 0),
      finished_(std::max<std::size_t>(lanes, 1), 0),
      errors_(std::max<std::size_t>(lanes, 1)) {
  for (std::size_t lane = 1; lane < lanes; ++lane) workers_.emplace_back([this, lane] { serve(lane); });
}

CheckPool::~CheckPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

bool CheckPool::claim(std::size_t lane, std::uint64_t generation) {
  if (claimed_[lane] == generation) return false;
  claimed_[lane] = generation;
  return true;
}

void CheckPool::serve(std::size_t lane) {
  std::uint64_t seen = 0;
  for (;;) {
    const std::function<void(std::size_t)>* work = nullptr;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      work = work_;
      if (!claim(lane, seen)) continue;  // the caller did this lane's share itself
    }
    try {
      (*work)(lane);
    } catch (...) {
      errors_[lane] = std::current_exception();
    }
    std::lock_guard lock(mutex_);
    finished_[lane] = seen;
    done_.notify_all();
  }
}

void CheckPool::run(const std::function<void(std::size_t)>& work) {
  std::uint64_t generation = 0;
  {
    std::lock_guard lock(mutex_);
    std::fill(errors_.begin(), errors_.end(), nullptr);
    work_ = &work;
    generation = ++generation_;
    claim(0, generation);
  }
  wake_.notify_all();
  // Lane 0 here, then every share no worker has taken yet (a worker slow to wake on a busy machine
  // costs nothing but the wake-up).
  for (std::size_t lane = 0; lane < claimed_.size(); ++lane) {
    if (lane > 0) {
      std::lock_guard lock(mutex_);
      if (!claim(lane, generation)) continue;
    }
    try {
      work(lane);
    } catch (...) {
      errors_[lane] = std::current_exception();
    }
    if (lane > 0) {
      std::lock_guard lock(mutex_);
      finished_[lane] = generation;
    }
  }
  std::unique_lock lock(mutex_);
  done_.wait(lock, [&] {
    for (std::size_t lane = 1; lane < claimed_.size(); ++lane)
      if (finished_[lane] != generation) return false;
    return true;
  });
  for (const std::exception_ptr& e : errors_)
    if (e) std::rethrow_exception(e);
}

}  // namespace dash
