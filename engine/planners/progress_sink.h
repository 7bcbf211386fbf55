#pragma once
// Progress for people on a terminal: phase, iteration, representation sizes and elapsed time, at most
// a few lines per second. Fed by the planner's event stream like any other sink.
#include <cstdio>
#include <mutex>

#include "engine/core/stopwatch.h"
#include "engine/events/events.h"

namespace dash {

class ProgressSink final : public log::EventSink {
 public:
  /// `verbose`: also print every constraint and task space expansion as it happens.
  explicit ProgressSink(std::FILE* out, bool verbose = false, double period_seconds = 0.5)
      : out_(out), verbose_(verbose), period_(period_seconds) {}
  void onEvent(const log::Event& event) override;
  /// Prints the current line now (e.g. at the end of a run).
  void flush();

 private:
  void print();

  std::FILE* out_;
  bool verbose_;
  double period_;
  std::mutex mutex_;
  Stopwatch clock_;
  double last_print_ = -1e9;
  int iteration_ = 0;
  log::Phase phase_ = log::Phase::Other;
  std::size_t counts_[log::kLayerCount][2] = {};
  std::size_t constraints_ = 0;
};

}  // namespace dash
