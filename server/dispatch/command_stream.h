#pragma once
// The queue behind one agent's server-sent event stream: the service pushes formatted events, the
// HTTP worker that serves the stream waits on it and writes them out at once.
#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <string>
#include <vector>

namespace dash::dispatch {

class CommandStream {
 public:
  /// Queues one formatted event (formatSse). Ignored once closed.
  void push(std::string event) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (closed_) return;
      events_.push_back(std::move(event));
    }
    cv_.notify_all();
  }
  /// Ends the stream: next() returns false from now on.
  void close() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      closed_ = true;
    }
    cv_.notify_all();
  }
  bool closed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return closed_;
  }
  /// Waits up to `timeout` for events and moves them into `out` (empty on a timeout).
  /// Returns false when the stream is closed.
  bool next(std::vector<std::string>& out, std::chrono::microseconds timeout) {
    std::unique_lock<std::mutex> lock(mutex_);
    cv_.wait_for(lock, timeout, [&] { return closed_ || !events_.empty(); });
    if (closed_) return false;
    while (!events_.empty()) {
      out.push_back(std::move(events_.front()));
      events_.pop_front();
    }
    return true;
  }

 private:
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<std::string> events_;
  bool closed_ = false;
};

}  // namespace dash::dispatch
