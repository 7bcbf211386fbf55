#pragma once
// Progress for people on a terminal: phase (and how long it has run), iteration, representation sizes
// ("building" for a layer its construction phase has not reported yet) and elapsed time, at most a few
// lines per second. Fed by the planner's event stream like any other sink. While a long phase
// reports its progress (events.h ProgressEvent: conflict resolution's steps scheduled of the plan's,
// the step's robots, steps per second) the line carries it too. A ticker thread (startTicker) prints
// the latest line again when nothing was printed for a while, so a single long step still shows the
// clock moving; it only reads what the events left, so the planner computes the same with or without it.
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>

#include "engine/core/stopwatch.h"
#include "engine/events/events.h"

namespace dash {

class ProgressSink final : public log::EventSink {
 public:
  /// `verbose`: also print every constraint and task space expansion as it happens.
  explicit ProgressSink(std::FILE* out, bool verbose = false, double period_seconds = 0.5)
      : out_(out), verbose_(verbose), period_(period_seconds) {}
  ~ProgressSink() override;
  void onEvent(const log::Event& event) override;
  /// Prints the current line now (e.g. at the end of a run).
  void flush();
  /// From now until stopTicker (or destruction), a thread prints the current line again whenever
  /// nothing was printed for `quiet_seconds`.
  void startTicker(double quiet_seconds = 1.0);
  void stopTicker();

  /// The progress part of the line ("steps 37/146 (ur5e_3, ur5e_7) 4.2 steps/s"), empty when no long
  /// phase is reporting. For tests.
  static std::string formatWork(const log::ProgressEvent& p);
  /// "H_M 12/40", or "H_M building" for a layer still empty while `building` (its construction phase
  /// runs). For tests.
  static std::string formatLayer(const char* name, std::size_t vertices, std::size_t hyperarcs, bool building);

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
  double phase_started_ = 0;  ///< clock_ time the current phase started
  std::size_t counts_[log::kLayerCount][2] = {};
  std::size_t constraints_ = 0;
  log::ProgressEvent work_;  ///< the latest progress event
  bool working_ = false;     ///< a long phase's work reported and not ended (work_.current not empty)
  bool shown_ = false;       ///< a line showed that work running

  std::thread ticker_;
  std::condition_variable ticker_cv_;
  bool ticker_stop_ = false;
};

}  // namespace dash
